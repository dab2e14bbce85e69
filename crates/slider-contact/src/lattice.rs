//! The compliance operator C of all N posts of the slider on their square lattice, applied as a
//! zero-padded FFT convolution in O(N log N) (DC-FFT: S. Liu, Q. Wang & G. Liu, Wear 243 (2000)
//! 101): C_ij depends only on the lattice offset of posts i and j, so C·f is a linear (not
//! circular) 2D convolution, computed exactly on a grid padded to the smallest 3-smooth
//! lengths ≥ 2n − 1 ([`padded_length`]).
//!
//! **Two scales.** With r the centre distance of posts i ≠ j and a the post radius:
//!
//! C_ij = c_stator(r) + c_body(r),  C_ii = 1/k_sn + s_post + ΔK(0),
//!
//! - near field, the post's own cell (scale a … pitch): the stator's rigid-disk sink
//!   1/k_sn = (1−ν)/(4Ga) (exact, Johnson §3.8) and the slider side s_post: by default the
//!   Johnson bonded punch 1/k_pn (docs/physics.md §3, post column not counted), or a value taken from
//!   the strip FEM's condensed compliance ([`crate::calibration`]) that contains the 2 µm post,
//!   its fillet-free base and the mesh of the one-off cell FEM;
//! - far field, between posts (scale pitch … slider): the stator is an elastic half-space, a
//!   rigid disk displacing the surface at distance r by c_stator(r) = (1−ν)/(2πGa)·arcsin(a/r)
//!   (Johnson eq. 3.36, [`static_contact::halfspace`]); the slider body is a layer of thickness t
//!   bonded to a rigid back: the same disk term with the slider's G, ν plus the smooth rigid-back
//!   correction ΔK(r) of [`crate::layer`] (scale t).
//!
//! The mutual terms treat the post bases as frictionless rigid disks (the bonded base adds a
//! radial traction whose net effect at distance r is a dipole, O(a/r)² relative) and the far field
//! as unbounded laterally (the 0.5 mm margins and free edges of the real slider are not resolved).
//!
//! **Precision.** The transforms run in f64 ([`Precision::Double`], the product to rounding) or,
//! through [`ComplianceOperator::apply_at`] with [`Precision::Single`], in f32 with f64 forces
//! and displacements: the product to ≈ 1e-7 of ‖C f‖ ≤ ‖C‖‖f‖ (measured 7e-8 … 1.5e-7 relative
//! in L2 on 40 × 37 … 100 × 100 lattices, for contact loads and loads of alternating sign), for
//! the inner iterations of a solver that checks its answer on a double product.

use std::sync::Arc;

use contact_springs::Material;
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftNum, FftPlanner};
use static_contact::halfspace::{disk_mutual_compliance, disk_self_compliance};

use crate::error::{Result, invalid};
use crate::layer::LayerCorrection;

/// Arithmetic of a compliance product's transforms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// f64 throughout: the product to rounding (≈ 1e-16 of ‖C‖‖f‖).
    #[default]
    Double,
    /// The FFT convolution's transforms and spectrum product in f32, input and output f64:
    /// the product to ≈ 1e-7 of ‖C‖‖f‖, for the inner iterations of a solver that checks its
    /// answer on a double product (an inexact Newton step, an iterative refinement's
    /// correction). Operators without transforms (dense, plate) compute in double.
    Single,
}

/// What a contact solver needs of a compliance: its size, C·f and its diagonal.
pub trait ComplianceOperator {
    /// Number of posts.
    fn len(&self) -> usize;
    /// Whether there are no posts.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// out = C·f (m, for f in N).
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]);
    /// out = C·f in the given `precision` ([`Precision::Single`]: an operator without a
    /// single-precision product computes in double, its only arithmetic).
    fn apply_at(&self, force_n: &[f64], out_m: &mut [f64], precision: Precision) {
        let _ = precision;
        self.apply(force_n, out_m);
    }
    /// The diagonal C_ii (m/N).
    fn diagonal(&self) -> Vec<f64>;
}

/// A dense compliance matrix (m/N) as an operator (tests, small problems).
impl ComplianceOperator for nalgebra::DMatrix<f64> {
    fn len(&self) -> usize {
        self.nrows()
    }
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]) {
        let f = nalgebra::DVectorView::from_slice(force_n, force_n.len());
        let u = self * f;
        out_m.copy_from_slice(u.as_slice());
    }
    fn diagonal(&self) -> Vec<f64> {
        (0..self.nrows()).map(|i| self[(i, i)]).collect()
    }
}

/// The post lattice of the slider: n_x × n_y posts at pitch p, centred on the slider.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LatticeGeometry {
    /// Posts along x (the wave's direction).
    pub posts_x: usize,
    /// Posts along y.
    pub posts_y: usize,
    /// Post pitch in x and y (m).
    pub pitch_m: f64,
    /// Post radius a (m).
    pub post_radius_m: f64,
    /// Slider length along x (m), ≥ n_x·p (the rest is the margin).
    pub slider_length_m: f64,
    /// Slider width along y (m), ≥ n_y·p.
    pub slider_width_m: f64,
}

impl LatticeGeometry {
    /// Number of posts.
    pub fn len(&self) -> usize {
        self.posts_x * self.posts_y
    }

    /// Whether there are no posts.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of post (i along x, j along y): i·n_y + j.
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * self.posts_y + j
    }

    /// Post centre x (m) from the slider's −x edge: margin + (i + ½)p (as the strip mesh).
    pub fn x_m(&self, i: usize) -> f64 {
        0.5 * (self.slider_length_m - self.posts_x as f64 * self.pitch_m)
            + (i as f64 + 0.5) * self.pitch_m
    }

    /// Post centre y (m) from the slider's −y edge.
    pub fn y_m(&self, j: usize) -> f64 {
        0.5 * (self.slider_width_m - self.posts_y as f64 * self.pitch_m)
            + (j as f64 + 0.5) * self.pitch_m
    }

    /// Checks counts and sizes; errors name the field.
    pub fn validate(&self) -> Result<()> {
        if self.posts_x == 0 || self.posts_y == 0 {
            return Err(invalid(
                "posts_x",
                (self.posts_x * self.posts_y) as f64,
                "the lattice needs at least one post in x and in y",
            ));
        }
        for (field, v) in [
            ("post_pitch_m", self.pitch_m),
            ("post_diameter_m", self.post_radius_m),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(field, v, "must be positive and finite"));
            }
        }
        if 2.0 * self.post_radius_m >= self.pitch_m {
            return Err(invalid(
                "post_diameter_m",
                2.0 * self.post_radius_m,
                format!("must be smaller than the pitch {} m", self.pitch_m),
            ));
        }
        let (lx, ly) = (
            self.posts_x as f64 * self.pitch_m,
            self.posts_y as f64 * self.pitch_m,
        );
        if self.slider_length_m.is_nan() || self.slider_length_m < lx * (1.0 - 1e-9) {
            return Err(invalid(
                "slider_length_m",
                self.slider_length_m,
                format!("shorter than the post array ({lx} m)"),
            ));
        }
        if self.slider_width_m.is_nan() || self.slider_width_m < ly * (1.0 - 1e-9) {
            return Err(invalid(
                "slider_width_m",
                self.slider_width_m,
                format!("narrower than the post array ({ly} m)"),
            ));
        }
        Ok(())
    }
}

/// The slider side's near field s_post (m/N): the post's own compliance on the slider body.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum NearField {
    /// Johnson's bonded rigid punch on a half-space, 1/k_pn (docs/physics.md §3).
    #[default]
    Johnson,
    /// A given value (m/N), e.g. from the strip FEM ([`crate::calibration`]).
    Value {
        /// s_post (m/N).
        slider_self_compliance_m_per_n: f64,
    },
}

/// Everything the operator depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatorSpec {
    /// Lattice.
    pub geometry: LatticeGeometry,
    /// Slider material.
    pub slider_material: Material,
    /// Stator material.
    pub stator_material: Material,
    /// Slider body thickness t above the posts (m), bonded to a rigid back.
    pub slider_thickness_m: f64,
    /// The slider side's own post compliance.
    pub near_field: NearField,
}

/// The parts of the diagonal (m/N), for reports.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DiagonalParts {
    /// Stator rigid-disk sink 1/k_sn.
    pub stator_self_m_per_n: f64,
    /// Slider post near field s_post.
    pub slider_self_m_per_n: f64,
    /// Rigid-back correction at r = 0, ΔK(0) (< 0).
    pub layer_at_zero_m_per_n: f64,
}

impl DiagonalParts {
    /// C_ii (m/N).
    pub fn total_m_per_n(&self) -> f64 {
        self.stator_self_m_per_n + self.slider_self_m_per_n + self.layer_at_zero_m_per_n
    }
}

/// The lattice kernel c(r) for all post offsets, before the FFT.
#[derive(Debug, Clone)]
pub struct LatticeKernel {
    spec: OperatorSpec,
    layer: LayerCorrection,
    parts: DiagonalParts,
}

impl LatticeKernel {
    /// Tabulates the rigid-back correction and the diagonal parts.
    pub fn new(spec: &OperatorSpec) -> Result<Self> {
        spec.geometry.validate()?;
        for (field, m) in [
            ("slider_material", &spec.slider_material),
            ("stator_material", &spec.stator_material),
        ] {
            m.validate()
                .map_err(|e| invalid(field, m.shear_modulus_pa, e.to_string()))?;
        }
        let t = spec.slider_thickness_m;
        if !(t > 0.0 && t.is_finite()) {
            return Err(invalid(
                "slider_thickness_m",
                t,
                "must be positive and finite",
            ));
        }
        let g = &spec.geometry;
        let a = g.post_radius_m;
        let diagonal_m = g.pitch_m * (g.posts_x as f64).hypot(g.posts_y as f64);
        let layer = LayerCorrection::new(
            spec.slider_material.shear_modulus_pa,
            spec.slider_material.poisson_ratio,
            t,
            diagonal_m,
        );
        let slider_self_m_per_n = match spec.near_field {
            NearField::Johnson => {
                let k = contact_springs::k_pn(&spec.slider_material, a)
                    .map_err(|e| invalid("post_diameter_m", 2.0 * a, e.to_string()))?;
                1.0 / k
            }
            NearField::Value {
                slider_self_compliance_m_per_n: s,
            } => {
                if !(s >= 0.0 && s.is_finite()) {
                    return Err(invalid(
                        "slider_self_compliance_m_per_n",
                        s,
                        "must be non-negative and finite",
                    ));
                }
                s
            }
        };
        let parts = DiagonalParts {
            stator_self_m_per_n: disk_self_compliance(
                spec.stator_material.shear_modulus_pa,
                spec.stator_material.poisson_ratio,
                a,
            ),
            slider_self_m_per_n,
            layer_at_zero_m_per_n: layer.at(0.0),
        };
        Ok(Self {
            spec: spec.clone(),
            layer,
            parts,
        })
    }

    /// The diagonal's parts.
    pub fn parts(&self) -> DiagonalParts {
        self.parts
    }

    /// The slider body's mutual compliance at distance r > 0 (m/N): disk term + ΔK(r).
    pub fn body_mutual(&self, r_m: f64) -> f64 {
        let m = &self.spec.slider_material;
        disk_mutual_compliance(
            m.shear_modulus_pa,
            m.poisson_ratio,
            self.spec.geometry.post_radius_m,
            r_m,
        ) + self.layer.at(r_m)
    }

    /// The stator's mutual compliance at distance r > 0 (m/N).
    pub fn stator_mutual(&self, r_m: f64) -> f64 {
        let m = &self.spec.stator_material;
        disk_mutual_compliance(
            m.shear_modulus_pa,
            m.poisson_ratio,
            self.spec.geometry.post_radius_m,
            r_m,
        )
    }

    /// C between two posts at lattice offset (di, dj) (m/N).
    pub fn at_offset(&self, di: i64, dj: i64) -> f64 {
        if di == 0 && dj == 0 {
            return self.parts.total_m_per_n();
        }
        let r = self.spec.geometry.pitch_m * (di as f64).hypot(dj as f64);
        self.body_mutual(r) + self.stator_mutual(r)
    }

    /// The dense matrix C (m/N), n × n (small lattices: tests and the dense reference solve).
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        let g = &self.spec.geometry;
        let n = g.len();
        nalgebra::DMatrix::from_fn(n, n, |p, q| {
            let (ip, jp) = ((p / g.posts_y) as i64, (p % g.posts_y) as i64);
            let (iq, jq) = ((q / g.posts_y) as i64, (q % g.posts_y) as i64);
            self.at_offset(ip - iq, jp - jq)
        })
    }
}

/// The padded FFT length for n posts: the smallest 2^a 3^b ≥ 2n − 1 (a linear convolution of
/// offsets −(n−1)…n−1 needs ≥ 2n − 1 points). rustfft's speed depends on the length's factors:
/// a large prime factor (142 = 2·71) falls back to a slower algorithm (measured 5× slower for
/// 71 × 71 posts), and its radix-5 passes are slower per point than radix 2 and 3 (one f64
/// transform with AVX: 200 = 2³·5² 0.37 µs, 216 = 2³·3³ 0.30 µs), so the default slider's 100
/// posts pad to 216, not 200: 15 % less transform time for 8 % more points.
pub fn padded_length(n: usize) -> usize {
    let smooth = |mut m: usize| {
        for p in [2, 3] {
            while m.is_multiple_of(p) {
                m /= p;
            }
        }
        m == 1
    };
    (2 * n - 1..)
        .find(|&m| smooth(m))
        .expect("a 3-smooth number exists")
}

/// The float type of a product's transforms: f64 ([`Precision::Double`]) or f32
/// ([`Precision::Single`]); forces enter and displacements leave as f64.
trait TransformFloat: FftNum {
    /// x rounded to this type (exact for f64).
    fn narrow(x: f64) -> Self;
    /// The value as f64 (exact).
    fn widen(self) -> f64;
}

impl TransformFloat for f64 {
    fn narrow(x: f64) -> Self {
        x
    }
    fn widen(self) -> f64 {
        self
    }
}

impl TransformFloat for f32 {
    fn narrow(x: f64) -> Self {
        x as f32
    }
    fn widen(self) -> f64 {
        self as f64
    }
}

/// The transforms of one float type: forward and inverse plans of lengths P_x and P_y, their
/// largest scratch, and the kernel's real spectrum in that type, column-major on the padded
/// grid (index c·P_x + r), columns c = 0 … P_y/2 only (the rest follow by symmetry).
#[derive(Clone)]
struct Transforms<T: FftNum> {
    fft_x: Arc<dyn Fft<T>>,
    fft_y: Arc<dyn Fft<T>>,
    ifft_x: Arc<dyn Fft<T>>,
    ifft_y: Arc<dyn Fft<T>>,
    scratch_len: usize,
    spectrum: Vec<T>,
}

impl<T: TransformFloat> Transforms<T> {
    /// The four plans of the P_x × P_y grid, with `spectrum`.
    fn new(px: usize, py: usize, spectrum: Vec<T>) -> Self {
        let mut planner = FftPlanner::<T>::new();
        let (fft_x, fft_y) = (planner.plan_fft_forward(px), planner.plan_fft_forward(py));
        let (ifft_x, ifft_y) = (planner.plan_fft_inverse(px), planner.plan_fft_inverse(py));
        let scratch_len = [&fft_x, &fft_y, &ifft_x, &ifft_y]
            .iter()
            .map(|f| f.get_inplace_scratch_len())
            .max()
            .unwrap_or(0);
        Self {
            fft_x,
            fft_y,
            ifft_x,
            ifft_y,
            scratch_len,
            spectrum,
        }
    }
}

/// C as a zero-padded FFT convolution on the P_x × P_y grid, P ≥ 2n − 1 (module doc).
#[derive(Clone)]
pub struct LatticeOperator {
    nx: usize,
    ny: usize,
    px: usize,
    py: usize,
    diagonal_m_per_n: f64,
    /// f64 plans and spectrum ([`Precision::Double`], the reference).
    double: Transforms<f64>,
    /// f32 plans and the f64 spectrum rounded to f32 ([`Precision::Single`]).
    single: Transforms<f32>,
    parts: DiagonalParts,
}

impl std::fmt::Debug for LatticeOperator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LatticeOperator")
            .field("posts_x", &self.nx)
            .field("posts_y", &self.ny)
            .field("diagonal_m_per_n", &self.diagonal_m_per_n)
            .finish()
    }
}

impl LatticeOperator {
    /// Builds the kernel and its spectrum (once).
    pub fn new(spec: &OperatorSpec) -> Result<Self> {
        let kernel = LatticeKernel::new(spec)?;
        Ok(Self::from_kernel(&kernel))
    }

    /// The operator of a tabulated kernel.
    pub fn from_kernel(kernel: &LatticeKernel) -> Self {
        Self::from_offsets(&kernel.spec.geometry, kernel.parts, |di, dj| {
            kernel.at_offset(di, dj)
        })
    }

    /// The operator of any kernel c(di, dj) on `geometry`'s lattice that is even in each offset
    /// separately, c(−di, dj) = c(di, dj) = c(di, −dj) (the normal kernel, radial, and the
    /// tangential one, which depends on di² and dj²): its padded-grid spectrum is then real
    /// (the one FFT convolution of the lattice for every direction). `parts` are the diagonal's
    /// (C_ii = `parts.total_m_per_n()`, which must equal c(0, 0)). The spectrum is computed in
    /// f64; the single-precision product uses it rounded to f32.
    pub fn from_offsets(
        geometry: &LatticeGeometry,
        parts: DiagonalParts,
        kernel: impl Fn(i64, i64) -> f64,
    ) -> Self {
        let (nx, ny) = (geometry.posts_x, geometry.posts_y);
        let (px, py) = (padded_length(nx), padded_length(ny));
        let mut double = Transforms::<f64>::new(px, py, Vec::new());
        double.spectrum = kernel_spectrum(&double, px, py, kernel);
        let single_spectrum = double.spectrum.iter().map(|&s| f32::narrow(s)).collect();
        Self {
            nx,
            ny,
            px,
            py,
            diagonal_m_per_n: parts.total_m_per_n(),
            single: Transforms::new(px, py, single_spectrum),
            double,
            parts,
        }
    }

    /// The diagonal's parts.
    pub fn parts(&self) -> DiagonalParts {
        self.parts
    }
}

/// The real spectrum of `kernel` on the P_x × P_y grid, non-negative y-wavenumbers only
/// (layout of [`Transforms`]'s `spectrum`). The kernel is placed at wrapped offsets; offsets of
/// |d| ≥ n (never used by the linear convolution) also get c(d), so that the grid kernel stays
/// even and its spectrum real.
fn kernel_spectrum(
    transforms: &Transforms<f64>,
    px: usize,
    py: usize,
    kernel: impl Fn(i64, i64) -> f64,
) -> Vec<f64> {
    let wrap = |k: usize, p: usize| -> i64 {
        if 2 * k <= p {
            k as i64
        } else {
            k as i64 - p as i64
        }
    };
    let mut a: Vec<Complex<f64>> = (0..px * py)
        .map(|idx| {
            let (r, c) = (idx / py, idx % py);
            Complex::new(kernel(wrap(r, px), wrap(c, py)), 0.0)
        })
        .collect();
    transforms.fft_y.process(&mut a);
    let mut b = transpose(&a, px, py);
    transforms.fft_x.process(&mut b);
    // Only the non-negative y-wavenumbers are used (real data, `apply`).
    b[..(py / 2 + 1) * px].iter().map(|z| z.re).collect()
}

/// b[c·rows + r] = a[r·cols + c].
fn transpose(a: &[Complex<f64>], rows: usize, cols: usize) -> Vec<Complex<f64>> {
    let mut b = vec![Complex::new(0.0, 0.0); rows * cols];
    for r in 0..rows {
        for c in 0..cols {
            b[c * rows + r] = a[r * cols + c];
        }
    }
    b
}

/// The work arrays of one [`LatticeOperator`] product: the y-transforms of the row pairs, one
/// block of x-columns (non-negative y-wavenumbers) and the transforms' scratch. Kept per thread
/// and float type, grown to the largest lattice the thread has applied.
struct ProductBuffers<T> {
    rows: Vec<Complex<T>>,
    columns: Vec<Complex<T>>,
    scratch: Vec<Complex<T>>,
}

impl<T> Default for ProductBuffers<T> {
    fn default() -> Self {
        Self {
            rows: Vec::new(),
            columns: Vec::new(),
            scratch: Vec::new(),
        }
    }
}

thread_local! {
    static DOUBLE_BUFFERS: std::cell::RefCell<ProductBuffers<f64>> =
        std::cell::RefCell::new(ProductBuffers::default());
    static SINGLE_BUFFERS: std::cell::RefCell<ProductBuffers<f32>> =
        std::cell::RefCell::new(ProductBuffers::default());
}

/// Columns (y-wavenumbers) transformed along x at a time. Their gather reads 4 adjacent
/// entries (a cache line in f64) of every row pair at k and at P_y − k, and the block
/// (4 × P_x complex, 14 kB in f64 for the default slider) stays in L1 from its gather through
/// both x-transforms and the spectrum product to its scatter back into the rows, where a pass
/// per step over all P_y/2 + 1 columns (377 kB) went through L2 five times. Default slider:
/// 131–137 → 125–130 µs per double product; 2 and 8 columns time the same. What remains of the
/// shuffles (≈ 10 µs each way) is their complex arithmetic, not memory traffic.
const COLUMNS_PER_BLOCK: usize = 4;

impl LatticeOperator {
    /// [`ComplianceOperator::apply_at`] with `transforms` on the given work arrays: the row
    /// pairs' y-transforms; per block of non-negative y-wavenumbers, its columns' x-transforms,
    /// the product with the spectrum and the inverse x-transforms; the inverse y-transforms.
    fn apply_with<T: TransformFloat>(
        &self,
        transforms: &Transforms<T>,
        force_n: &[f64],
        out_m: &mut [f64],
        buffers: &mut ProductBuffers<T>,
    ) {
        assert_eq!(force_n.len(), self.nx * self.ny, "one force per post");
        assert_eq!(out_m.len(), self.nx * self.ny, "one displacement per post");
        let (px, py) = (self.px, self.py);
        let zero = Complex::new(T::narrow(0.0), T::narrow(0.0));
        let (half, pairs) = (py / 2 + 1, self.nx.div_ceil(2));
        let ProductBuffers {
            rows,
            columns,
            scratch,
        } = buffers;
        rows.resize(pairs * py, zero);
        columns.resize(COLUMNS_PER_BLOCK * px, zero);
        scratch.resize(transforms.scratch_len, zero);
        let rows = &mut rows[..pairs * py];
        self.pack_rows(force_n, rows);
        transforms.fft_y.process_with_scratch(rows, scratch);
        for first in (0..half).step_by(COLUMNS_PER_BLOCK) {
            let block = first..(first + COLUMNS_PER_BLOCK).min(half);
            let columns = &mut columns[..block.len() * px];
            self.rows_to_columns(rows, block.clone(), columns);
            transforms.fft_x.process_with_scratch(columns, scratch);
            for (z, &s) in columns.iter_mut().zip(&transforms.spectrum[first * px..]) {
                *z = *z * s;
            }
            transforms.ifft_x.process_with_scratch(columns, scratch);
            self.columns_to_rows(columns, block, rows);
        }
        transforms.ifft_y.process_with_scratch(rows, scratch);
        self.unpack_rows(rows, out_m);
    }

    /// Rows 2m and 2m + 1 of `force_n` as the real and imaginary parts of padded row m.
    fn pack_rows<T: TransformFloat>(&self, force_n: &[f64], rows: &mut [Complex<T>]) {
        let (ny, py) = (self.ny, self.py);
        let zero = T::narrow(0.0);
        for (pair, row) in force_n.chunks(2 * ny).zip(rows.chunks_exact_mut(py)) {
            let (even, odd) = pair.split_at(ny);
            if odd.is_empty() {
                for (z, &re) in row.iter_mut().zip(even) {
                    *z = Complex::new(T::narrow(re), zero);
                }
            } else {
                for ((z, &re), &im) in row.iter_mut().zip(even).zip(odd) {
                    *z = Complex::new(T::narrow(re), T::narrow(im));
                }
            }
            row[ny..].fill(Complex::new(zero, zero));
        }
    }

    /// The row pairs' y-spectra at the y-wavenumbers `block` (all < P_y/2 + 1) unpacked into one
    /// column of length P_x each (rows n_x.. zero): row 2m's spectrum
    /// (Z_m[k] + conj Z_m[P_y − k])/2, row 2m + 1's (Z_m[k] − conj Z_m[P_y − k])/(2i).
    fn rows_to_columns<T: TransformFloat>(
        &self,
        rows: &[Complex<T>],
        block: std::ops::Range<usize>,
        columns: &mut [Complex<T>],
    ) {
        let (nx, px, py) = (self.nx, self.px, self.py);
        let zero = T::narrow(0.0);
        let (half, minus_half_i) = (T::narrow(0.5), Complex::new(zero, T::narrow(-0.5)));
        let mut conjugate = [0; COLUMNS_PER_BLOCK];
        for (c, k) in conjugate.iter_mut().zip(block.clone()) {
            *c = (py - k) % py;
        }
        let wavenumbers = || block.clone().zip(&conjugate);
        let (pair_rows, last_row) = rows.split_at(nx / 2 * py);
        for (m, row) in pair_rows.chunks_exact(py).enumerate() {
            for ((k, &c), column) in wavenumbers().zip(columns.chunks_exact_mut(px)) {
                let (zk, zc) = (row[k], row[c].conj());
                column[2 * m] = (zk + zc) * half;
                column[2 * m + 1] = (zk - zc) * minus_half_i;
            }
        }
        for ((k, &c), column) in wavenumbers().zip(columns.chunks_exact_mut(px)) {
            if nx % 2 == 1 {
                let (zk, zc) = (last_row[k], last_row[c].conj());
                column[nx - 1] = (zk + zc) * half;
            }
            column[nx..].fill(Complex::new(zero, zero));
        }
    }

    /// The columns of y-wavenumbers `block` repacked into the row pairs: row i's y-spectrum
    /// G_i[k] = columns[(k − block.start)·P_x + i], G_i[P_y − k] = conj G_i[k] (for
    /// 0 < k ≤ P_y − (P_y/2 + 1)); row pair m is G_2m + i G_2m+1 (G_nx = 0).
    fn columns_to_rows<T: TransformFloat>(
        &self,
        columns: &[Complex<T>],
        block: std::ops::Range<usize>,
        rows: &mut [Complex<T>],
    ) {
        let (nx, px, py) = (self.nx, self.px, self.py);
        let mirrored = 1..py - py / 2;
        let zero = T::narrow(0.0);
        let (i_unit, i_zero) = (Complex::new(zero, T::narrow(1.0)), Complex::new(zero, zero));
        let put = |row: &mut [Complex<T>], k: usize, even: Complex<T>, odd: [Complex<T>; 2]| {
            row[k] = even + i_unit * odd[0];
            if mirrored.contains(&k) {
                row[py - k] = even.conj() + i_unit * odd[1];
            }
        };
        let (pair_rows, last_row) = rows.split_at_mut(nx / 2 * py);
        for (m, row) in pair_rows.chunks_exact_mut(py).enumerate() {
            for (k, column) in block.clone().zip(columns.chunks_exact(px)) {
                let odd = column[2 * m + 1];
                put(row, k, column[2 * m], [odd, odd.conj()]);
            }
        }
        if nx % 2 == 1 {
            for (k, column) in block.zip(columns.chunks_exact(px)) {
                put(last_row, k, column[nx - 1], [i_zero, i_zero]);
            }
        }
    }

    /// The inverse-transformed row pairs, scaled by 1/(P_x P_y) in f64, into rows 2m and 2m + 1
    /// of `out_m`.
    fn unpack_rows<T: TransformFloat>(&self, rows: &[Complex<T>], out_m: &mut [f64]) {
        let (ny, py) = (self.ny, self.py);
        let scale = 1.0 / (self.px * py) as f64;
        for (pair, row) in out_m.chunks_mut(2 * ny).zip(rows.chunks_exact(py)) {
            let (even, odd) = pair.split_at_mut(ny);
            for (u, z) in even.iter_mut().zip(row) {
                *u = z.re.widen() * scale;
            }
            for (u, z) in odd.iter_mut().zip(row) {
                *u = z.im.widen() * scale;
            }
        }
    }
}

impl ComplianceOperator for LatticeOperator {
    fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Real data, two x-rows per complex transform: rows 2m and 2m + 1 ride as the real and
    /// imaginary parts of one y-transform (Z = F₂ₘ + i F₂ₘ₊₁, unpacked by the Hermitian symmetry
    /// of a real row's spectrum), so only the P_y/2 + 1 non-negative y-wavenumbers are
    /// transformed along x, four columns at a time that stay in L1 cache; the product with the
    /// real, even spectrum keeps every row's spectrum Hermitian, and the inverse repacks two rows
    /// again. Half the transforms of a plain complex 2D convolution, the same result to rounding.
    /// The work arrays are the calling thread's, kept between products: a product allocates
    /// nothing once its thread has made one. The transforms are f64 ([`Precision::Double`]);
    /// [`ComplianceOperator::apply_at`] with [`Precision::Single`] runs the same algorithm in
    /// f32.
    fn apply(&self, force_n: &[f64], out_m: &mut [f64]) {
        self.apply_at(force_n, out_m, Precision::Double);
    }

    /// [`Precision::Double`]: [`ComplianceOperator::apply`]. [`Precision::Single`]: the same
    /// convolution with f32 plans, the spectrum rounded to f32 and f32 work arrays (the calling
    /// thread's, kept as the double ones); the forces are rounded to f32 when packed and the
    /// displacements widened to f64 before the 1/(P_x P_y) scale. Error ≈ 1e-7 of ‖C f‖
    /// (module doc) for half the memory traffic and twice the SIMD width: 83 µs against 130 µs
    /// for the default slider's product.
    fn apply_at(&self, force_n: &[f64], out_m: &mut [f64], precision: Precision) {
        match precision {
            Precision::Double => DOUBLE_BUFFERS
                .with_borrow_mut(|buffers| self.apply_with(&self.double, force_n, out_m, buffers)),
            Precision::Single => SINGLE_BUFFERS
                .with_borrow_mut(|buffers| self.apply_with(&self.single, force_n, out_m, buffers)),
        }
    }

    fn diagonal(&self) -> Vec<f64> {
        vec![self.diagonal_m_per_n; self.len()]
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small lattice at the paper's pitch and post radius (Si on LiNbO₃, 0.1 mm back,
    /// Johnson near field): the operators' tests compare their products on it.
    pub(crate) fn small_spec(nx: usize, ny: usize) -> OperatorSpec {
        OperatorSpec {
            geometry: LatticeGeometry {
                posts_x: nx,
                posts_y: ny,
                pitch_m: 40e-6,
                post_radius_m: 10e-6,
                slider_length_m: nx as f64 * 40e-6,
                slider_width_m: ny as f64 * 40e-6,
            },
            slider_material: Material::silicon(),
            stator_material: Material::lithium_niobate(),
            slider_thickness_m: 0.1e-3,
            near_field: NearField::Johnson,
        }
    }

    #[test]
    fn the_fft_convolution_equals_the_dense_product() {
        // Odd and even row counts (the rows ride in pairs), a single row, a single column.
        for (nx, ny) in [(7, 5), (6, 4), (1, 6), (5, 1)] {
            let n = nx * ny;
            let kernel = LatticeKernel::new(&small_spec(nx, ny)).unwrap();
            let op = LatticeOperator::from_kernel(&kernel);
            let dense = kernel.to_dense();
            let f: Vec<f64> = (0..n)
                .map(|i| ((i * 37 % 11) as f64 - 3.0) * 1e-3)
                .collect();
            let mut u_fft = vec![0.0; n];
            op.apply(&f, &mut u_fft);
            let mut u_dense = vec![0.0; n];
            dense.apply(&f, &mut u_dense);
            let scale = u_dense.iter().map(|u| u.abs()).fold(0.0, f64::max);
            for i in 0..n {
                assert!(
                    (u_fft[i] - u_dense[i]).abs() < 1e-12 * scale,
                    "displacement of post {i} of {nx} × {ny}: FFT {} vs dense {}",
                    u_fft[i],
                    u_dense[i]
                );
            }
        }
    }

    /// A contact-like load (N) on n posts: ≈ 4 mN per post varying by ±50 %, every seventh
    /// post out of contact.
    fn contact_load(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| match i % 7 {
                3 => 0.0,
                _ => 4e-3 * (1.0 + 0.5 * (0.37 * i as f64).sin()),
            })
            .collect()
    }

    /// The single-precision product's error against the double one: ‖Δu‖₂/‖u‖₂ and
    /// max|Δu|/max|u|.
    fn single_precision_error(op: &LatticeOperator, force_n: &[f64]) -> (f64, f64) {
        let n = force_n.len();
        let (mut double, mut single) = (vec![0.0; n], vec![0.0; n]);
        op.apply(force_n, &mut double);
        op.apply_at(force_n, &mut single, Precision::Single);
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
        let max = |v: &mut dyn Iterator<Item = f64>| v.map(f64::abs).fold(0.0, f64::max);
        let difference = || double.iter().zip(&single).map(|(d, s)| s - d);
        (
            norm(&mut difference()) / norm(&mut double.iter().copied()),
            max(&mut difference()) / max(&mut double.iter().copied()),
        )
    }

    #[test]
    fn the_single_precision_product_agrees_with_the_double_to_1e_6() {
        // Even and odd post counts (the rows ride in pairs), up to the default slider's lattice.
        for (nx, ny) in [(40, 37), (41, 29), (100, 100)] {
            let op = LatticeOperator::new(&small_spec(nx, ny)).unwrap();
            let (l2, entry) = single_precision_error(&op, &contact_load(nx * ny));
            eprintln!("{nx} × {ny}: single vs double {l2:.2e} (L2), {entry:.2e} (max entry)");
            assert!(l2 <= 1e-6, "{nx} × {ny}: relative L2 error {l2:e}");
            assert!(
                entry <= 1e-5,
                "{nx} × {ny}: entry-wise error {entry:e} of max|u|"
            );
        }
    }

    #[test]
    fn double_precision_via_apply_at_is_apply_bit_for_bit() {
        let op = LatticeOperator::new(&small_spec(41, 29)).unwrap();
        let f = contact_load(41 * 29);
        let (mut a, mut b) = (vec![0.0; f.len()], vec![0.0; f.len()]);
        op.apply(&f, &mut a);
        op.apply_at(&f, &mut b, Precision::Double);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b));
    }

    #[test]
    fn padded_lengths_are_smooth_and_long_enough() {
        assert_eq!(padded_length(100), 216, "100 posts: 199 → 216 = 2³·3³");
        assert_eq!(padded_length(71), 144, "71 posts: 141 → 144 = 2⁴·3²");
        assert_eq!(padded_length(5), 9, "5 posts: 9 = 3²");
        assert_eq!(padded_length(1), 1, "one post");
    }

    #[test]
    fn the_fft_convolution_is_exact_with_odd_padded_lengths() {
        // 5 × 14 posts pad to 9 × 27 (odd lengths, Nyquist-free).
        let kernel = LatticeKernel::new(&small_spec(5, 14)).unwrap();
        let op = LatticeOperator::from_kernel(&kernel);
        let dense = kernel.to_dense();
        let n = 5 * 14;
        let f: Vec<f64> = (0..n).map(|i| ((i * 13 % 7) as f64 - 2.5) * 1e-3).collect();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        op.apply(&f, &mut a);
        dense.apply(&f, &mut b);
        let scale = b.iter().map(|u| u.abs()).fold(0.0, f64::max);
        for i in 0..n {
            assert!(
                (a[i] - b[i]).abs() < 1e-12 * scale,
                "displacement of post {i}: FFT {} vs dense {}",
                a[i],
                b[i]
            );
        }
    }

    #[test]
    fn the_lattice_compliance_is_symmetric_positive_definite() {
        let dense = LatticeKernel::new(&small_spec(6, 6)).unwrap().to_dense();
        assert!(
            (&dense - dense.transpose()).abs().max() < 1e-15 * dense.abs().max(),
            "compliance symmetry"
        );
        let eig = dense.symmetric_eigenvalues();
        assert!(
            eig.min() > 0.0,
            "smallest compliance eigenvalue {}",
            eig.min()
        );
    }

    #[test]
    fn the_rigid_back_stiffens_the_body_and_its_far_field_vanishes() {
        let kernel = LatticeKernel::new(&small_spec(40, 1)).unwrap();
        assert!(
            kernel.parts().layer_at_zero_m_per_n < 0.0,
            "rigid-back correction at r = 0 must reduce the compliance"
        );
        // Beyond several thicknesses (t = 0.1 mm) the bonded layer hardly moves.
        let r = 1.5e-3;
        let half_space = kernel.body_mutual(r) - kernel.layer.at(r);
        assert!(
            kernel.body_mutual(r).abs() < 1e-3 * half_space,
            "body mutual compliance at 15 t: {} vs half-space {}",
            kernel.body_mutual(r),
            half_space
        );
    }
}
