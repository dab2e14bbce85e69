//! Crystal cuts: a material with the Euler angles of its wave frame, and the named cuts.
//!
//! Formula: a cut is (material, (φ, θ, ψ)) in the ZXZ convention of [`crate::rotation`]; a
//! θ_Y-rotated Y-cut with X propagation has Euler angles (0°, θ_Y − 90°, 0°). Source of the named
//! cuts: A. J. Slobodnik et al., *Microwave Acoustics Handbook* vol. 1A (1973); K. Yamanouchi,
//! K. Shibayama, "Propagation and amplification of Rayleigh waves and piezoelectric leaky surface
//! waves in LiNbO3", *J. Appl. Phys.* 43, 856 (1972) for 128° Y-X. Range of validity: any finite
//! Euler angles; the named cuts are the three of the table below.
//!
//! The cut is the input of [`crate::wave`], which also holds [`Cut::solve`], so this module
//! does not depend on the solver.

use crate::error::WaveError;
use crate::material::Material;
use crate::materials;
use crate::rotation::EulerAngles;

/// A crystal cut: the material in its crystal axes and the wave frame's Euler angles.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Cut {
    /// Name of the cut (e.g. `128yx-linbo3`).
    pub name: String,
    /// The crystal, constants in its own (IEEE) axes.
    pub material: Material,
    /// Wave frame: x′₁ propagation, x′₃ outward normal.
    pub euler: EulerAngles,
}

/// A named cut: name, constructor of its constant set, Euler angles (degrees).
type NamedCut = (&'static str, fn() -> Material, EulerAngles);

/// The named cuts.
const NAMED_CUTS: [NamedCut; 3] = [
    (
        "128yx-linbo3",
        materials::lithium_niobate_kovacs_1990,
        EulerAngles::new(0.0, 38.0, 0.0),
    ),
    (
        "yz-linbo3",
        materials::lithium_niobate_kovacs_1990,
        EulerAngles::new(0.0, 90.0, 90.0),
    ),
    (
        "st-x-quartz",
        materials::quartz_bechmann_1958,
        EulerAngles::new(0.0, 132.75, 0.0),
    ),
];

impl Cut {
    /// Names accepted by [`Cut::from_name`].
    pub const KNOWN_NAMES: [&'static str; 3] = [NAMED_CUTS[0].0, NAMED_CUTS[1].0, NAMED_CUTS[2].0];

    /// A cut of any material at any Euler angles.
    pub fn new(name: impl Into<String>, material: Material, euler: EulerAngles) -> Self {
        Self {
            name: name.into(),
            material,
            euler,
        }
    }

    /// One of the named cuts (LiNbO3 with the Kovacs et al. 1990 constants, quartz with
    /// Bechmann's): `128yx-linbo3` (0°, 38°, 0°), `yz-linbo3` (0°, 90°, 90°), `st-x-quartz`
    /// (0°, 132.75°, 0°). The name is matched case-insensitively.
    pub fn from_name(name: &str) -> Result<Self, WaveError> {
        let wanted = name.trim().to_ascii_lowercase();
        NAMED_CUTS
            .iter()
            .find(|(known, _, _)| *known == wanted)
            .map(|(known, material, euler)| Self::new(*known, material(), *euler))
            .ok_or_else(|| WaveError::UnknownCut {
                name: name.to_owned(),
                known: Self::KNOWN_NAMES.join(", "),
            })
    }

    /// The material's constants in the wave frame.
    pub fn rotated_material(&self) -> Material {
        self.material.rotated(&self.euler)
    }

    /// A readable label: name, material and Euler angles.
    pub fn label(&self) -> String {
        let e = &self.euler;
        format!(
            "{} ({}, Euler {}°, {}°, {}°)",
            self.name, self.material.name, e.phi_deg, e.theta_deg, e.psi_deg
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_cut_error_lists_every_known_cut() {
        let err = Cut::from_name("36yx-litao3").unwrap_err();
        let text = err.to_string();
        assert!(text.contains("36yx-litao3"), "{text}");
        for name in Cut::KNOWN_NAMES {
            assert!(text.contains(name), "{text} lacks {name}");
        }
    }

    #[test]
    fn named_cuts_are_found_case_insensitively() {
        let cut = Cut::from_name(" 128YX-LiNbO3 ").unwrap();
        assert_eq!(cut.name, "128yx-linbo3");
        assert_eq!(cut.euler, EulerAngles::new(0.0, 38.0, 0.0));
    }
}
