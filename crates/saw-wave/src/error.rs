//! The one error type of the crate.
//!
//! Formula: none. Source: the workspace convention (one `thiserror` enum per library crate whose
//! `Display` names the parameter, material, cut or velocity at fault). Valid for every public
//! function of the crate: none of them panics on user input.

use std::fmt;

/// Which electrical boundary condition a surface wave was sought for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Surface {
    /// Vacuum above the crystal: the potential continues into a decaying vacuum field (ε0).
    Free,
    /// A thin perfect conductor on the surface: the potential is zero there (shorted).
    Metallized,
}

impl fmt::Display for Surface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Surface::Free => f.write_str("electrically free"),
            Surface::Metallized => f.write_str("metallized"),
        }
    }
}

/// Everything that can go wrong when a crystal cut's surface wave is computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WaveError {
    /// `Cut::from_name` was given a name that is not in the table.
    #[error("unknown crystal cut `{name}`; known cuts: {known}")]
    UnknownCut {
        /// The name that was asked for.
        name: String,
        /// The known names, comma separated.
        known: String,
    },
    /// A material constant, Euler angle or argument is NaN or infinite.
    #[error("non-finite {quantity} of `{context}`: {value}")]
    NonFinite {
        /// The material, cut or function the value belongs to.
        context: String,
        /// Which constant (e.g. `stiffness c_14`, `Euler angle theta`).
        quantity: String,
        /// The offending value.
        value: f64,
    },
    /// The density is zero or negative.
    #[error("non-positive density {density_kg_per_m3} kg/m³ of material `{material}`")]
    NonPositiveDensity {
        /// The material.
        material: String,
        /// The offending density.
        density_kg_per_m3: f64,
    },
    /// A symmetric tensor (stiffness or permittivity) is not symmetric.
    #[error(
        "{tensor} of material `{material}` is not symmetric: entry ({row}, {col}) differs from ({col}, {row})"
    )]
    NotSymmetric {
        /// The material.
        material: String,
        /// `stiffness` or `permittivity`.
        tensor: &'static str,
        /// Row of the offending entry (1-based Voigt or tensor index).
        row: usize,
        /// Column of the offending entry (1-based).
        col: usize,
    },
    /// The stiffness or permittivity has a non-positive eigenvalue: the material is unstable.
    #[error(
        "{tensor} of material `{material}` is not positive definite (smallest eigenvalue {smallest_eigenvalue:e})"
    )]
    NotPositiveDefinite {
        /// The material.
        material: String,
        /// `stiffness` or `permittivity`.
        tensor: &'static str,
        /// The smallest eigenvalue, in the tensor's SI unit.
        smallest_eigenvalue: f64,
    },
    /// The boundary determinant has no root below the limiting velocity: the only surface
    /// waves of this cut are leaky (they radiate into the bulk) or there is none.
    #[error(
        "no surface wave on the {surface} surface of `{cut}` below the limiting velocity {limiting_velocity_m_per_s:.3} m/s: the wave is leaky or absent"
    )]
    NoSurfaceWave {
        /// The cut (material and Euler angles).
        cut: String,
        /// Free or metallized.
        surface: Surface,
        /// The lowest velocity at which a partial wave stops decaying into the substrate.
        limiting_velocity_m_per_s: f64,
    },
    /// The surface wave found has no normal displacement, so it cannot be normalised to u_z
    /// (a pure shear-horizontal wave such as a Bleustein–Gulyaev wave).
    #[error(
        "the surface wave on the {surface} surface of `{cut}` at {velocity_m_per_s:.3} m/s has no normal displacement (|u_z|/|u| = {normal_fraction:e})"
    )]
    NoNormalDisplacement {
        /// The cut.
        cut: String,
        /// Free or metallized.
        surface: Surface,
        /// The wave's phase velocity.
        velocity_m_per_s: f64,
        /// |u_z| / |(u_x, u_y, u_z)| at the surface.
        normal_fraction: f64,
    },
    /// The eigenvalue solver of the partial-wave (Stroh) matrix did not converge, or the
    /// partial waves do not span the surface fields.
    #[error("partial-wave solution failed for `{cut}` at {velocity_m_per_s:.6} m/s: {reason}")]
    PartialWaves {
        /// The cut.
        cut: String,
        /// The trial velocity.
        velocity_m_per_s: f64,
        /// What failed.
        reason: &'static str,
    },
    /// A field of an interdigital transducer, of its metallisation or of its drive is out of
    /// range (named as in [`crate::idt::Idt`] and [`crate::idt::Idt::drive`]).
    #[error("invalid interdigital transducer {field} = {value}: {requirement}")]
    InvalidIdt {
        /// The field (e.g. `finger_width_m`, `metallisation.thickness_m`, `drive_voltage_peak_v`).
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A transducer substrate was built from a wave solved for another cut.
    #[error(
        "the wave was solved for `{wave_cut}`, not for the cut `{cut}` of the transducer substrate"
    )]
    MismatchedWave {
        /// The cut given.
        cut: String,
        /// The cut the wave belongs to.
        wave_cut: String,
    },
    /// An argument of a power or profile function is out of range.
    #[error("invalid argument {name} = {value} of {function}: {requirement}")]
    InvalidArgument {
        /// The function.
        function: &'static str,
        /// The argument.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
}
