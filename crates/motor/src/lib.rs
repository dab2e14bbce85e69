#![doc = include_str!("../README.md")]

pub mod input;
pub mod paper;
pub mod rng;

pub use contact_springs::Material;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One motor, SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Motor {
    /// The stator's travelling wave.
    pub wave: Wave,
    /// Stator material (the half-space the wave travels on).
    pub stator: Material,
    /// The stator's crystal cut: the substrate whose Rayleigh wave drives the slider (scene
    /// key `stator.cut`; reading a motor without it gives the paper's 128° Y-X LiNbO3).
    #[serde(default = "StatorCut::paper")]
    pub stator_cut: StatorCut,
    /// The slider body.
    pub slider: SliderBody,
    /// The post array on the slider's face.
    pub posts: PostArray,
    /// Coulomb friction at the post tips.
    pub friction: Friction,
    /// Forces on the slider.
    pub load: Load,
    /// What a real slider has besides the ideal lattice: post-height scatter, a measured
    /// height map, tilt and bow (none for the paper's ideal motor).
    #[serde(default)]
    pub imperfections: Imperfections,
}

impl Motor {
    /// The paper's motor (docs/physics.md §1): 9.61 MHz Rayleigh wave of 20 nm on 128° YX
    /// LiNbO3, V_t = 1.1 m/s; Si slider 5 × 5 × 0.5 mm with 100 × 100 posts of 20 µm diameter,
    /// 2 µm high, on a 4 × 4 mm array; μ = 0.3; preload 40 N.
    pub fn paper() -> Self {
        use paper::*;
        let slider_material = Material::silicon();
        Self {
            wave: Wave::from_tangential_velocity(
                FREQUENCY_HZ,
                NORMAL_AMPLITUDE_M,
                TANGENTIAL_VELOCITY_M_PER_S,
                PHASE_VELOCITY_M_PER_S,
            ),
            stator: Material::lithium_niobate(),
            stator_cut: StatorCut::paper(),
            slider: SliderBody::with_geometric_mass(
                slider_material,
                SLIDER_SIDE_M,
                SLIDER_SIDE_M,
                SLIDER_THICKNESS_M,
            ),
            posts: PostArray {
                diameter_m: POST_DIAMETER_M,
                height_m: POST_HEIGHT_M,
                count_x: POSTS_PER_SIDE,
                count_y: POSTS_PER_SIDE,
                array_x_m: ARRAY_SIDE_M,
                array_y_m: ARRAY_SIDE_M,
            },
            friction: Friction {
                mu_static: FRICTION_COEFFICIENT,
                mu_kinetic: FRICTION_COEFFICIENT,
            },
            load: Load {
                preload_n: PRELOAD_N,
                external_load_n: 0.0,
                mechanism: PreloadMechanism::Rigid,
            },
            imperfections: Imperfections::default(),
        }
    }

    /// Whether the motor is the ideal one the strip model of one post row resolves exactly:
    /// identical rows (no scatter, map, tilt or bow) on a rigid back. `None` if so, else the
    /// scene key of the first feature that breaks it.
    pub fn first_non_ideal_key(&self) -> Option<&'static str> {
        let i = &self.imperfections;
        if i.height_scatter_m != 0.0 {
            Some("posts.height_scatter")
        } else if i.height_map.is_some() {
            Some("posts.height_map")
        } else if i.tilt_x_m != 0.0 {
            Some("slider.tilt_x")
        } else if i.tilt_y_m != 0.0 {
            Some("slider.tilt_y")
        } else if i.bow_m != 0.0 {
            Some("slider.bow")
        } else if self.load.mechanism != PreloadMechanism::Rigid {
            Some("load.mechanism")
        } else {
            None
        }
    }

    /// Mass of one post, ρ_slider π d² h / 4 (kg).
    pub fn post_mass_kg(&self) -> f64 {
        self.slider.material.density_kg_per_m3 * self.posts.tip_area_m2() * self.posts.height_m
    }
}

/// The stator's crystal cut: a crystal constant set and the Euler angles of the wave frame
/// (x₁ propagation, x₃ outward normal), as crate `saw-wave` defines them. This crate only
/// describes the cut; `saw-wave` solves its Rayleigh wave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatorCut {
    /// Name: a named cut (`128yx-linbo3`, `yz-linbo3`, `st-x-quartz`) or, for a cut given by
    /// its Euler angles, the crystal and `euler` (e.g. `linbo3 euler`).
    pub name: String,
    /// The crystal's constant set, e.g. `LiNbO3 (Kovacs et al. 1990)`.
    pub crystal: String,
    /// ZXZ Euler angles (φ, θ, ψ) of the wave frame (degrees).
    pub euler_deg: [f64; 3],
}

impl StatorCut {
    /// The paper's cut: 128° Y-X LiNbO3, Kovacs et al. constants, Euler (0°, 38°, 0°).
    pub fn paper() -> Self {
        Self {
            name: paper::STATOR_CUT.into(),
            crystal: paper::STATOR_CRYSTAL.into(),
            euler_deg: paper::STATOR_CUT_EULER_DEG,
        }
    }
}

/// The interdigital transducer (IDT) that launches the stator's wave: a uniform
/// single-electrode comb of `finger_pairs` pairs of fingers of width `finger_width_m` separated
/// by gaps `gap_m`, overlapping over `aperture_m` (the beam's width). This crate only describes
/// it; `saw_wave::idt` turns a drive voltage into the wave (scene keys `[stator.idt]`,
/// `wave.drive_voltage`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Transducer {
    /// Finger pairs N_p (2N_p fingers).
    pub finger_pairs: u32,
    /// Finger width w (m).
    pub finger_width_m: f64,
    /// Gap between neighbouring fingers g (m).
    pub gap_m: f64,
    /// Acoustic aperture W, the fingers' overlap (m).
    pub aperture_m: f64,
}

impl Transducer {
    /// The paper's transducer (section 3, Fig. 4): 20 pairs, 100 µm fingers and gaps
    /// (period λ₀ = 400 µm), 9 mm aperture; the film is not given (perfect conductors).
    pub fn paper() -> Self {
        Self {
            finger_pairs: paper::IDT_FINGER_PAIRS,
            finger_width_m: paper::IDT_FINGER_WIDTH_M,
            gap_m: paper::IDT_GAP_M,
            aperture_m: paper::APERTURE_M,
        }
    }

    /// Transducer period λ₀ = 2(w + g) (m): the wavelength at synchronism.
    pub fn period_m(&self) -> f64 {
        2.0 * (self.finger_width_m + self.gap_m)
    }
}

/// The stator's surface wave (docs/physics.md §4): a Rayleigh wave travelling along +x with an
/// elliptical retrograde orbit, w = A_n sin θ, u = A_t cos θ, θ = ωt − kx.
///
/// * `decay_length_m`: amplitudes scale as exp(−x/L) along +x (x measured from the slider
///   centre at t = 0), e.g. attenuation under the slider. `None`: no decay.
/// * `burst_periods`: a finite burst of n periods: at each material point the wave is on for
///   0 ≤ θ < 2πn and the surface is at rest before and after (the burst front reaches the
///   slider centre at t = 0). `None`: continuous wave.
/// * `aperture_m`: the beam's width across y, the IDT's aperture: the wave carries its power
///   per unit width over this width (reading a wave without it gives the paper's 9 mm).
///
/// Its JSON also carries the derived `tangential_velocity_m_per_s` (A_t ω) and `wavelength_m`
/// for the reader; reading accepts and ignores them (they are recomputed).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(from = "WaveJson")]
pub struct Wave {
    /// Drive frequency f (Hz).
    pub frequency_hz: f64,
    /// Normal displacement amplitude A_n (m).
    pub normal_amplitude_m: f64,
    /// Tangential displacement amplitude A_t (m); the tangential velocity amplitude is A_t ω.
    pub tangential_amplitude_m: f64,
    /// Phase velocity c of the wave along +x (m/s).
    pub phase_velocity_m_per_s: f64,
    /// Amplitude decay length along +x (m), if any.
    #[serde(default)]
    pub decay_length_m: Option<f64>,
    /// Burst length in wave periods, if the drive is a finite burst.
    pub burst_periods: Option<f64>,
    /// Width of the wave's beam across y (m): the aperture of the IDT that launches it.
    pub aperture_m: f64,
}

/// A wave as written: the fields and the derived values, which reading ignores.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WaveJson {
    frequency_hz: f64,
    normal_amplitude_m: f64,
    tangential_amplitude_m: f64,
    phase_velocity_m_per_s: f64,
    #[serde(default)]
    decay_length_m: Option<f64>,
    #[serde(default)]
    burst_periods: Option<f64>,
    #[serde(default = "paper_aperture_m")]
    aperture_m: f64,
    #[serde(default, rename = "tangential_velocity_m_per_s")]
    _tangential_velocity_m_per_s: Option<f64>,
    #[serde(default, rename = "wavelength_m")]
    _wavelength_m: Option<f64>,
}

impl From<WaveJson> for Wave {
    fn from(w: WaveJson) -> Self {
        Self {
            frequency_hz: w.frequency_hz,
            normal_amplitude_m: w.normal_amplitude_m,
            tangential_amplitude_m: w.tangential_amplitude_m,
            phase_velocity_m_per_s: w.phase_velocity_m_per_s,
            decay_length_m: w.decay_length_m,
            burst_periods: w.burst_periods,
            aperture_m: w.aperture_m,
        }
    }
}

fn paper_aperture_m() -> f64 {
    paper::APERTURE_M
}

impl Serialize for Wave {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut s = serializer.serialize_struct("Wave", 9)?;
        s.serialize_field("frequency_hz", &self.frequency_hz)?;
        s.serialize_field("normal_amplitude_m", &self.normal_amplitude_m)?;
        s.serialize_field("tangential_amplitude_m", &self.tangential_amplitude_m)?;
        s.serialize_field("phase_velocity_m_per_s", &self.phase_velocity_m_per_s)?;
        s.serialize_field("decay_length_m", &self.decay_length_m)?;
        s.serialize_field("burst_periods", &self.burst_periods)?;
        s.serialize_field("aperture_m", &self.aperture_m)?;
        s.serialize_field("tangential_velocity_m_per_s", &self.crest_speed_m_per_s())?;
        s.serialize_field("wavelength_m", &self.wavelength_m())?;
        s.end()
    }
}

impl Wave {
    /// The paper's wave: f = 9.61 MHz, A_n = 20 nm, V_t = 1.1 m/s, c = 3979 m/s, continuous, in a
    /// 9 mm beam.
    pub fn paper_default() -> Self {
        Motor::paper().wave
    }

    /// A continuous wave given the tangential *velocity* amplitude V_t (A_t = V_t/ω), in a beam
    /// of the paper's aperture (9 mm).
    pub fn from_tangential_velocity(
        frequency_hz: f64,
        normal_amplitude_m: f64,
        tangential_velocity_m_per_s: f64,
        phase_velocity_m_per_s: f64,
    ) -> Self {
        Self {
            frequency_hz,
            normal_amplitude_m,
            tangential_amplitude_m: tangential_velocity_m_per_s / (2.0 * PI * frequency_hz),
            phase_velocity_m_per_s,
            decay_length_m: None,
            burst_periods: None,
            aperture_m: paper::APERTURE_M,
        }
    }

    /// Angular frequency ω = 2πf (rad/s).
    pub fn angular_frequency_rad_per_s(&self) -> f64 {
        2.0 * PI * self.frequency_hz
    }

    /// Wave period T = 1/f (s).
    pub fn period_s(&self) -> f64 {
        1.0 / self.frequency_hz
    }

    /// Wavelength λ = c/f (m).
    pub fn wavelength_m(&self) -> f64 {
        self.phase_velocity_m_per_s / self.frequency_hz
    }

    /// Wavenumber k = ω/c (rad/m).
    pub fn wavenumber_rad_per_m(&self) -> f64 {
        self.angular_frequency_rad_per_s() / self.phase_velocity_m_per_s
    }

    /// Crest speed V_t = A_t ω (m/s): the tangential surface velocity at the crest, an upper
    /// bound of the slider's no-load speed.
    pub fn crest_speed_m_per_s(&self) -> f64 {
        self.tangential_amplitude_m * self.angular_frequency_rad_per_s()
    }

    /// Surface strain k·max(A_n, A_t) (dimensionless).
    pub fn surface_strain(&self) -> f64 {
        self.wavenumber_rad_per_m() * self.normal_amplitude_m.max(self.tangential_amplitude_m)
    }
}

/// The slider body: a rectangular plate carrying the post array on its face.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderBody {
    /// Slider material.
    pub material: Material,
    /// Length along x, the wave's direction (m).
    pub length_m: f64,
    /// Width along y (m).
    pub width_m: f64,
    /// Body thickness above the posts (m).
    pub thickness_m: f64,
    /// Moving mass M (kg): the body's ρ·volume, or a given mass (with a holder, say).
    pub mass_kg: f64,
}

impl SliderBody {
    /// A body whose moving mass is its own, ρ · length · width · thickness.
    pub fn with_geometric_mass(
        material: Material,
        length_m: f64,
        width_m: f64,
        thickness_m: f64,
    ) -> Self {
        let mass_kg = material.density_kg_per_m3 * length_m * width_m * thickness_m;
        Self {
            material,
            length_m,
            width_m,
            thickness_m,
            mass_kg,
        }
    }

    /// ρ · length · width · thickness (kg): the body's own mass.
    pub fn geometric_mass_kg(&self) -> f64 {
        self.material.density_kg_per_m3 * self.length_m * self.width_m * self.thickness_m
    }
}

/// The post array: `count_x × count_y` cylindrical posts on a regular lattice filling
/// `array_x_m × array_y_m`, centred on the slider; pitch = array / count.
///
/// Its JSON also carries the derived `count`, `pitch_x_m`, `pitch_y_m` and `contact_area_m2`
/// for the reader (written, never read back: reading ignores them and recomputes).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(from = "PostArrayJson")]
pub struct PostArray {
    /// Post diameter d (m).
    pub diameter_m: f64,
    /// Post height h (m).
    pub height_m: f64,
    /// Posts along x (the wave's direction).
    pub count_x: u32,
    /// Posts along y.
    pub count_y: u32,
    /// Array extent along x (m).
    pub array_x_m: f64,
    /// Array extent along y (m).
    pub array_y_m: f64,
}

/// A post array as written: the fields and the derived values, which reading ignores.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PostArrayJson {
    diameter_m: f64,
    height_m: f64,
    count_x: u32,
    count_y: u32,
    array_x_m: f64,
    array_y_m: f64,
    #[serde(default, rename = "count")]
    _count: Option<u64>,
    #[serde(default, rename = "pitch_x_m")]
    _pitch_x_m: Option<f64>,
    #[serde(default, rename = "pitch_y_m")]
    _pitch_y_m: Option<f64>,
    #[serde(default, rename = "contact_area_m2")]
    _contact_area_m2: Option<f64>,
}

impl From<PostArrayJson> for PostArray {
    fn from(p: PostArrayJson) -> Self {
        Self {
            diameter_m: p.diameter_m,
            height_m: p.height_m,
            count_x: p.count_x,
            count_y: p.count_y,
            array_x_m: p.array_x_m,
            array_y_m: p.array_y_m,
        }
    }
}

impl Serialize for PostArray {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut s = serializer.serialize_struct("PostArray", 10)?;
        s.serialize_field("diameter_m", &self.diameter_m)?;
        s.serialize_field("height_m", &self.height_m)?;
        s.serialize_field("count_x", &self.count_x)?;
        s.serialize_field("count_y", &self.count_y)?;
        s.serialize_field("array_x_m", &self.array_x_m)?;
        s.serialize_field("array_y_m", &self.array_y_m)?;
        s.serialize_field("count", &self.count())?;
        s.serialize_field("pitch_x_m", &self.pitch_x_m())?;
        s.serialize_field("pitch_y_m", &self.pitch_y_m())?;
        s.serialize_field("contact_area_m2", &self.contact_area_m2())?;
        s.end()
    }
}

impl PostArray {
    /// Post radius a = d/2 (m).
    pub fn radius_m(&self) -> f64 {
        0.5 * self.diameter_m
    }

    /// Number of posts N = count_x · count_y.
    pub fn count(&self) -> u64 {
        u64::from(self.count_x) * u64::from(self.count_y)
    }

    /// Pitch along x, array_x / count_x (m).
    pub fn pitch_x_m(&self) -> f64 {
        self.array_x_m / f64::from(self.count_x)
    }

    /// Pitch along y, array_y / count_y (m).
    pub fn pitch_y_m(&self) -> f64 {
        self.array_y_m / f64::from(self.count_y)
    }

    /// Tip area of one post, π d²/4 (m²).
    pub fn tip_area_m2(&self) -> f64 {
        PI * self.diameter_m * self.diameter_m / 4.0
    }

    /// Total tip area N · π d²/4 (m²).
    pub fn contact_area_m2(&self) -> f64 {
        self.count() as f64 * self.tip_area_m2()
    }

    /// Whether the lattice is square (equal pitch in x and y within `relative` tolerance).
    pub fn is_square_lattice(&self, relative: f64) -> bool {
        (self.pitch_x_m() - self.pitch_y_m()).abs() <= relative * self.pitch_x_m()
    }

    /// x of each post column relative to the array centre (m), `count_x` values.
    pub fn column_x_m(&self) -> Vec<f64> {
        let centre = 0.5 * (f64::from(self.count_x) - 1.0);
        (0..self.count_x)
            .map(|j| (f64::from(j) - centre) * self.pitch_x_m())
            .collect()
    }
}

/// Coulomb friction at the post tips.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Friction {
    /// Static coefficient μ_s.
    pub mu_static: f64,
    /// Kinetic coefficient μ_k ≤ μ_s.
    pub mu_kinetic: f64,
}

/// Forces on the slider.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Load {
    /// Preload P pressing the slider onto the stator (N).
    pub preload_n: f64,
    /// Load opposing the drive (N): the operating point's thrust.
    #[serde(default)]
    pub external_load_n: f64,
    /// How the preload reaches the slider body.
    #[serde(default)]
    pub mechanism: PreloadMechanism,
}

/// How the preload reaches the slider body (scene key `load.mechanism`; the whole-slider
/// static model `slider_contact` resolves all three, the strip model only `Rigid`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum PreloadMechanism {
    /// The body's back is held flat by a rigid plate (bonded layer on a rigid back); its
    /// orientation is the clamp's (`slider.tilt_x`, `slider.tilt_y`).
    #[default]
    Rigid,
    /// A uniform pressure P/(L·W) on a free back: the body bends and rotates freely; the post
    /// forces balance P and its moments about the slider's centre.
    Pressure,
    /// A ball or pin pressing the free back at (x, y), measured from the slider's (−x, −y)
    /// corner (scene key `load.point`, e.g. "2.5 mm, 2.5 mm" for the default slider's centre).
    Point {
        /// x of the load point (m).
        x_m: f64,
        /// y of the load point (m).
        y_m: f64,
    },
}

impl PreloadMechanism {
    /// Whether the back is free (bends and rotates).
    pub fn is_free(&self) -> bool {
        !matches!(self, Self::Rigid)
    }

    /// The scene name: `rigid`, `pressure` or `point`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Rigid => "rigid",
            Self::Pressure => "pressure",
            Self::Point { .. } => "point",
        }
    }
}

/// A measured height map: one extra height δ (m) per post (positive: the post reaches further
/// towards the stator). Read from a CSV by `slider_contact::HeightMapCsv::read_csv`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightMap {
    /// The CSV it came from.
    pub file: String,
    /// δ (m) in lattice order (index i·count_y + j, i along x).
    pub height_m: Vec<f64>,
}

/// The imperfections of a real slider, SI (definitions and signs: `slider_contact::heights`,
/// docs/physics.md). All zero (the default): the ideal slider of identical posts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Imperfections {
    /// Standard deviation σ of the Gaussian post-height scatter (m), ≥ 0.
    pub height_scatter_m: f64,
    /// Seed of the scatter.
    pub scatter_seed: u64,
    /// A measured height map (added to the scatter; use σ = 0 for the map alone).
    pub height_map: Option<HeightMap>,
    /// Tilt τ_x: height change of the back across the slider length (m); the +x end higher.
    pub tilt_x_m: f64,
    /// Tilt τ_y: height change across the slider width (m).
    pub tilt_y_m: f64,
    /// Bow b: corners above the centre (m); b > 0 is convex towards the stator.
    pub bow_m: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn papers_transducer_has_a_400_um_period_and_the_beams_aperture() {
        let t = Transducer::paper();
        assert!((t.period_m() - 400e-6).abs() < 1e-18, "period 2(w + g)");
        assert_eq!(t.finger_pairs, 20, "finger pairs");
        assert_eq!(
            t.aperture_m,
            Motor::paper().wave.aperture_m,
            "the beam is the transducer's aperture"
        );
    }

    #[test]
    fn paper_motor_has_the_papers_derived_numbers() {
        let m = Motor::paper();
        assert!((m.posts.pitch_x_m() - 40e-6).abs() < 1e-18, "pitch 40 µm");
        assert_eq!(m.posts.count(), 10_000, "post count");
        assert!(
            (m.wave.crest_speed_m_per_s() - 1.1).abs() < 1e-12,
            "crest speed V_t = 1.1 m/s"
        );
        assert!(
            (m.wave.wavelength_m() - 3979.0 / 9.61e6).abs() < 1e-18,
            "wavelength c/f"
        );
        let mass = 2329.0 * 5e-3 * 5e-3 * 0.5e-3;
        assert!(
            (m.slider.mass_kg - mass).abs() < 1e-3 * mass,
            "slider mass ρ·volume of Si, got {} kg",
            m.slider.mass_kg
        );
    }

    #[test]
    fn motor_round_trips_through_json() {
        let m = Motor::paper();
        let back: Motor = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
        let mut real = Motor::paper();
        real.imperfections = Imperfections {
            height_scatter_m: 5e-9,
            scatter_seed: 7,
            height_map: Some(HeightMap {
                file: "h.csv".into(),
                height_m: vec![1e-9; 4],
            }),
            tilt_x_m: 2e-8,
            tilt_y_m: -1e-8,
            bow_m: 1e-8,
        };
        real.load.mechanism = PreloadMechanism::Point {
            x_m: 2.5e-3,
            y_m: 2e-3,
        };
        let back: Motor = serde_json::from_str(&serde_json::to_string(&real).unwrap()).unwrap();
        assert_eq!(back, real, "imperfections and mechanism survive the JSON");
    }

    #[test]
    fn the_cut_and_aperture_survive_the_json_and_default_to_the_papers() {
        let mut m = Motor::paper();
        assert_eq!(m.stator_cut.name, "128yx-linbo3");
        assert_eq!(m.wave.aperture_m, 9e-3);
        m.stator_cut = StatorCut {
            name: "st-x-quartz".into(),
            crystal: "alpha-quartz (Bechmann 1958)".into(),
            euler_deg: [0.0, 132.75, 0.0],
        };
        m.wave.aperture_m = 2e-3;
        let json = serde_json::to_value(&m).unwrap();
        assert_eq!(json["wave"]["aperture_m"], 2e-3);
        let back: Motor = serde_json::from_value(json.clone()).unwrap();
        assert_eq!(back, m, "cut and aperture read back");
        // A motor written before the cut and aperture were described reads as the paper's.
        let mut old = json;
        old.as_object_mut().unwrap().remove("stator_cut");
        old["wave"].as_object_mut().unwrap().remove("aperture_m");
        let back: Motor = serde_json::from_value(old).unwrap();
        assert_eq!(back.stator_cut, StatorCut::paper());
        assert_eq!(back.wave.aperture_m, paper::APERTURE_M);
    }

    #[test]
    fn the_paper_motor_is_ideal_and_each_imperfection_names_its_key() {
        let mut m = Motor::paper();
        assert_eq!(m.first_non_ideal_key(), None, "the paper's motor is ideal");
        m.imperfections.bow_m = 1e-9;
        assert_eq!(m.first_non_ideal_key(), Some("slider.bow"), "bow");
        m.imperfections.bow_m = 0.0;
        m.load.mechanism = PreloadMechanism::Pressure;
        assert_eq!(m.first_non_ideal_key(), Some("load.mechanism"), "mechanism");
    }
}
