//! The tangential (x) compliance operator of all N posts on their lattice: the x displacement of
//! post i's tip relative to the stator per unit x force on post j, C^t_ij (m/N), applied by the
//! same zero-padded FFT convolution as the normal operator ([`LatticeOperator::from_offsets`]).
//!
//! **Two scales, as the normal operator** ([`crate::lattice`]). With (dx, dy) the centre offset
//! of posts i ≠ j, r = |(dx, dy)| and a the post radius:
//!
//! C^t_ij = c_t,stator(dx, dy) + c_t,body(dx, dy),  C^t_ii = 1/k_st + s_t,post + ΔK_t(0),
//!
//! - near field, the post's own cell: the stator's rigid-disk tangential sink 1/k_st =
//!   (2−ν)/(8Ga) (Mindlin's rigid circular punch, Johnson §3.8 / §7.1: the traction
//!   q₀(1 − ρ²/a²)^{−1/2} gives a uniform tip displacement) and the slider side s_t,post: by
//!   default Johnson's bonded tangential punch 1/k_pt (docs/physics.md §3), or a value taken from
//!   the strip FEM's condensed tangential compliance ([`crate::calibration::calibrate_tangential_near_field`]);
//! - far field, between posts: both bodies are elastic half-spaces loaded by a tangential point
//!   force Q_x (Cerruti; Johnson, *Contact Mechanics* §2.2 eq. (2.19) at z = 0, i.e. eq.
//!   (3.86a)): u_x = Q_x/(2πG r)·[(1−ν) + ν dx²/r²], with the LiNbO3 constants for the stator
//!   and the Si ones for the slider body
//!   ([`static_contact::halfspace::tangential_mutual_compliance`], the formula's one home, which
//!   the strip's half-space stator also uses); the slider body is a layer of thickness t bonded
//!   to a rigid back, so it adds the smooth correction ΔK_t(dx, dy) of
//!   [`crate::layer::TangentialLayerCorrection`] (scale t).
//!
//! The kernel depends on dx² and dy² only (even in each offset, not radial: along the force
//! the point-force term is 1/(1−ν) times the one across it), so its padded-grid spectrum is
//! real and the normal operator's convolution serves unchanged.
//!
//! **Normal–tangential coupling.** A tangential force also moves the surface normally,
//! u_z = −(1−2ν) Q_x dx/(4πG r²) (Johnson eq. (3.86c)), odd in dx. Between two bodies only the
//! mismatch of the two bodies' terms acts on the interface; its size relative to the direct
//! terms is Dundurs' β ([`dundurs_beta`], Johnson eq. (5.53)). With the constants the operator
//! uses (Si G = 66.5 GPa, ν = 0.22; LiNbO3 G = 67.0 GPa, ν = 0.25) β = 0.0209 <
//! [`NEGLIGIBLE_DUNDURS_BETA`]: the coupling is **not kept** (Goodman's approximation, as the
//! strip's coupled model). The slider body's own cross term (the bonded layer tilting under a
//! tip shear) is not a half-space term and is not covered by β; on the strip FEM it is 0.035 of
//! the direct terms on the default 100-post row (crates/coupled-dynamics README).
//!
//! Valid as the normal operator: posts far (≫ a) apart compared with their radius (the point
//! form of the mutual terms is off by ≈ a²/(6r²), 1.0 % of the nearest neighbour's term at
//! r = 4a), loads farther than ≈ t from the slider's edges (the body is laterally unbounded),
//! friction forces along x only (the wave's direction; Q_x also moves the tips along y by
//! ν dx dy/(2πG r³), not modelled, as in the strip).

use contact_springs::Material;
use static_contact::halfspace::{
    disk_tangential_self_compliance, dundurs_beta as dundurs, tangential_mutual_compliance,
};

use crate::error::{Result, invalid};
use crate::lattice::{DiagonalParts, LatticeOperator, NearField, OperatorSpec};
use crate::layer::TangentialLayerCorrection;

/// Largest |β| (Dundurs' second parameter of the two bodies) for which the normal–tangential
/// coupling is dropped: the relative tangential displacement a normal pressure causes is then
/// below ≈ 5 % of the direct terms (Johnson §5.7). Dimensionless; default 0.05.
pub const NEGLIGIBLE_DUNDURS_BETA: f64 = 0.05;

/// Dundurs' β of the operator's two bodies (slider 1, stator 2), Johnson eq. (5.53).
pub fn dundurs_beta(spec: &OperatorSpec) -> f64 {
    let (s, t) = (&spec.slider_material, &spec.stator_material);
    dundurs(
        s.shear_modulus_pa,
        s.poisson_ratio,
        t.shear_modulus_pa,
        t.poisson_ratio,
    )
}

/// Whether the normal–tangential coupling may be dropped for these bodies
/// (|β| ≤ [`NEGLIGIBLE_DUNDURS_BETA`]).
pub fn coupling_negligible(spec: &OperatorSpec) -> bool {
    dundurs_beta(spec).abs() <= NEGLIGIBLE_DUNDURS_BETA
}

/// The tangential lattice kernel c_t(di, dj) for all post offsets, before the FFT.
#[derive(Debug, Clone)]
pub struct TangentialKernel {
    spec: OperatorSpec,
    layer: TangentialLayerCorrection,
    parts: DiagonalParts,
}

fn check_material(field: &'static str, m: &Material) -> Result<()> {
    m.validate()
        .map_err(|e| invalid(field, m.shear_modulus_pa, e.to_string()))
}

impl TangentialKernel {
    /// Tabulates the rigid-back correction and the diagonal parts. `near_field` is the slider
    /// side's own tangential post compliance: [`NearField::Johnson`] is Johnson's bonded
    /// tangential punch 1/k_pt; [`NearField::Value`] a calibrated s_t,post (m/N). The normal
    /// operator's `spec.near_field` is not used.
    pub fn new(spec: &OperatorSpec, near_field: NearField) -> Result<Self> {
        spec.geometry.validate()?;
        check_material("slider_material", &spec.slider_material)?;
        check_material("stator_material", &spec.stator_material)?;
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
        let m = &spec.slider_material;
        let layer =
            TangentialLayerCorrection::new(m.shear_modulus_pa, m.poisson_ratio, t, diagonal_m);
        let slider_self_m_per_n = match near_field {
            NearField::Johnson => {
                let k = contact_springs::k_pt(m, a)
                    .map_err(|e| invalid("post_diameter_m", 2.0 * a, e.to_string()))?;
                1.0 / k
            }
            NearField::Value {
                slider_self_compliance_m_per_n: s,
            } => {
                if !(s >= 0.0 && s.is_finite()) {
                    return Err(invalid(
                        "slider_tangential_self_compliance_m_per_n",
                        s,
                        "must be non-negative and finite",
                    ));
                }
                s
            }
        };
        let st = &spec.stator_material;
        let parts = DiagonalParts {
            stator_self_m_per_n: disk_tangential_self_compliance(
                st.shear_modulus_pa,
                st.poisson_ratio,
                a,
            ),
            slider_self_m_per_n,
            layer_at_zero_m_per_n: layer.at(0.0, 0.0),
        };
        Ok(Self {
            spec: spec.clone(),
            layer,
            parts,
        })
    }

    /// The diagonal's parts (tangential: 1/k_st, s_t,post, ΔK_t(0)).
    pub fn parts(&self) -> DiagonalParts {
        self.parts
    }

    /// The slider body's tangential mutual compliance at offset (dx, dy) ≠ 0 (m/N): Cerruti
    /// with the slider's constants + ΔK_t.
    pub fn body_mutual(&self, dx_m: f64, dy_m: f64) -> f64 {
        let m = &self.spec.slider_material;
        tangential_mutual_compliance(
            m.shear_modulus_pa,
            m.poisson_ratio,
            self.spec.geometry.post_radius_m,
            dx_m,
            dy_m,
        ) + self.layer.at(dx_m, dy_m)
    }

    /// The body's rigid-back correction ΔK_t at offset (dx, dy) (m/N), the origin included.
    pub fn body_layer(&self, dx_m: f64, dy_m: f64) -> f64 {
        self.layer.at(dx_m, dy_m)
    }

    /// The stator's tangential mutual compliance at offset (dx, dy) ≠ 0 (m/N): Cerruti.
    pub fn stator_mutual(&self, dx_m: f64, dy_m: f64) -> f64 {
        let m = &self.spec.stator_material;
        tangential_mutual_compliance(
            m.shear_modulus_pa,
            m.poisson_ratio,
            self.spec.geometry.post_radius_m,
            dx_m,
            dy_m,
        )
    }

    /// C^t between two posts at lattice offset (di along x, dj along y) (m/N).
    pub fn at_offset(&self, di: i64, dj: i64) -> f64 {
        if di == 0 && dj == 0 {
            return self.parts.total_m_per_n();
        }
        let p = self.spec.geometry.pitch_m;
        let (dx, dy) = (p * di as f64, p * dj as f64);
        self.body_mutual(dx, dy) + self.stator_mutual(dx, dy)
    }

    /// The dense matrix C^t (m/N), n × n, lattice order i·n_y + j (tests, the dense reference).
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        let g = &self.spec.geometry;
        let n = g.len();
        nalgebra::DMatrix::from_fn(n, n, |p, q| {
            let (ip, jp) = ((p / g.posts_y) as i64, (p % g.posts_y) as i64);
            let (iq, jq) = ((q / g.posts_y) as i64, (q % g.posts_y) as i64);
            self.at_offset(ip - iq, jp - jq)
        })
    }

    /// The FFT operator of this kernel.
    pub fn operator(&self) -> LatticeOperator {
        LatticeOperator::from_offsets(&self.spec.geometry, self.parts, |di, dj| {
            self.at_offset(di, dj)
        })
    }
}

impl LatticeOperator {
    /// The tangential (x) compliance operator of `spec`'s lattice with the slider side's
    /// tangential near field `near_field` ([`TangentialKernel::new`]).
    pub fn tangential(spec: &OperatorSpec, near_field: NearField) -> Result<Self> {
        Ok(TangentialKernel::new(spec, near_field)?.operator())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::ComplianceOperator;
    use crate::lattice::tests::small_spec as spec;

    #[test]
    fn the_tangential_fft_convolution_equals_the_dense_pairwise_sum() {
        for (nx, ny) in [(7, 5), (6, 4), (1, 6), (5, 1), (8, 5), (12, 9)] {
            let n = nx * ny;
            let kernel = TangentialKernel::new(&spec(nx, ny), NearField::Johnson).unwrap();
            let op = kernel.operator();
            let dense = kernel.to_dense();
            let f: Vec<f64> = (0..n)
                .map(|i| ((i * 37 % 11) as f64 - 3.0) * 1e-3)
                .collect();
            let (mut u_fft, mut u_dense) = (vec![0.0; n], vec![0.0; n]);
            op.apply(&f, &mut u_fft);
            dense.apply(&f, &mut u_dense);
            let scale = u_dense.iter().map(|u| u.abs()).fold(0.0, f64::max);
            for i in 0..n {
                assert!(
                    (u_fft[i] - u_dense[i]).abs() < 1e-12 * scale,
                    "tangential displacement of post {i} of {nx} × {ny}: FFT {} vs dense {}",
                    u_fft[i],
                    u_dense[i]
                );
            }
            assert_eq!(
                op.diagonal()[0],
                dense[(0, 0)],
                "tangential diagonal of {nx} × {ny}"
            );
        }
    }

    #[test]
    fn the_tangential_compliance_is_symmetric_positive_definite_and_anisotropic() {
        let kernel = TangentialKernel::new(&spec(6, 6), NearField::Johnson).unwrap();
        let dense = kernel.to_dense();
        assert!(
            (&dense - dense.transpose()).abs().max() < 1e-15 * dense.abs().max(),
            "tangential compliance symmetry"
        );
        let eig = dense.symmetric_eigenvalues();
        assert!(
            eig.min() > 0.0,
            "smallest tangential eigenvalue {}",
            eig.min()
        );
        assert!(
            kernel.at_offset(2, 0) > kernel.at_offset(0, 2),
            "along the force the tangential coupling is the larger: {} vs {}",
            kernel.at_offset(2, 0),
            kernel.at_offset(0, 2)
        );
        assert_eq!(
            kernel.at_offset(-2, 3),
            kernel.at_offset(2, -3),
            "even in each offset"
        );
    }

    #[test]
    fn the_diagonal_is_the_johnson_series_tangential_compliance_plus_the_back() {
        let s = spec(4, 4);
        let kernel = TangentialKernel::new(&s, NearField::Johnson).unwrap();
        let a = s.geometry.post_radius_m;
        let series = 1.0 / contact_springs::k_pt(&s.slider_material, a).unwrap()
            + 1.0 / contact_springs::k_st(&s.stator_material, a).unwrap();
        let p = kernel.parts();
        assert!(
            ((p.stator_self_m_per_n + p.slider_self_m_per_n) / series - 1.0).abs() < 1e-12,
            "tangential self compliance vs 1/k_pt + 1/k_st"
        );
        assert!(
            p.layer_at_zero_m_per_n < 0.0,
            "the rigid back stiffens the tangential self term: {}",
            p.layer_at_zero_m_per_n
        );
    }

    #[test]
    fn the_dundurs_beta_of_silicon_on_lithium_niobate_is_negligible() {
        let s = spec(2, 2);
        let beta = dundurs_beta(&s);
        // Independent evaluation with the tabulated constants (docs/physics.md §2).
        let (g1, n1, g2, n2) = (66.5e9, 0.22, 67.0e9, 0.25);
        let expected = 0.5 * ((1.0 - 2.0 * n1) / g1 - (1.0 - 2.0 * n2) / g2)
            / ((1.0 - n1) / g1 + (1.0 - n2) / g2);
        assert!((beta - expected).abs() < 1e-15, "β = {beta} vs {expected}");
        assert!(
            (beta - 0.0209).abs() < 1e-4,
            "Dundurs β of Si on LiNbO3 = {beta}"
        );
        assert!(coupling_negligible(&s), "β = {beta} is below the threshold");
        let mut soft = s.clone();
        soft.stator_material.shear_modulus_pa = 5e9;
        assert!(
            !coupling_negligible(&soft),
            "a soft stator's β = {} is not negligible",
            dundurs_beta(&soft)
        );
    }

    #[test]
    fn a_bad_tangential_near_field_is_refused_by_name() {
        let err = TangentialKernel::new(
            &spec(3, 3),
            NearField::Value {
                slider_self_compliance_m_per_n: -1.0,
            },
        )
        .unwrap_err();
        assert!(
            err.to_string()
                .contains("slider_tangential_self_compliance_m_per_n"),
            "{err}"
        );
    }
}
