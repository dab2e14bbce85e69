//! Table of crystal constant sets, each with its citation.
//!
//! Formula: the symmetry patterns of [`Material::trigonal_3m`] (LiNbO3) and
//! [`Material::trigonal_32`] (α-quartz) filled with published constants: c^E (Pa), e (C/m²),
//! ε^S (F/m, given as ε/ε0 in the sources), density (kg/m³). Source: the citation on each
//! function. Range of validity: room temperature (≈ 20–25 °C), small signals; the spread between
//! constant sets (e.g. ≈ 0.3 % in LiNbO3 SAW velocities, ≈ 10 % in K²) is the honest uncertainty
//! of any number computed from them.

use crate::material::{Material, VACUUM_PERMITTIVITY_F_PER_M as EPS0};

/// Congruent LiNbO3, constants of A. Kovacs, M. Stadler, G. Ruile, M. Pfeiffer, R. Weigel,
/// "Improved material constants for LiNbO3 and LiTaO3", *Proc. IEEE Ultrasonics Symposium*
/// 1990, pp. 435–438: c11 198.86, c12 54.67, c13 67.99, c14 7.83, c33 234.18, c44 59.85 GPa;
/// e15 3.69, e22 2.42, e31 0.30, e33 1.77 C/m²; ε11^S/ε0 44.3, ε33^S/ε0 27.9; ρ 4628 kg/m³.
pub fn lithium_niobate_kovacs_1990() -> Material {
    Material::trigonal_3m(
        "LiNbO3 (Kovacs et al. 1990)",
        [198.86e9, 54.67e9, 67.99e9, 7.83e9, 234.18e9, 59.85e9],
        [3.69, 2.42, 0.30, 1.77],
        [44.3 * EPS0, 27.9 * EPS0],
        4628.0,
    )
    .expect("the tabulated LiNbO3 constants are valid")
}

/// LiNbO3, constants of A. W. Warner, M. Onoe, G. A. Coquin, "Determination of elastic and
/// piezoelectric constants for crystals in class (3m)", *J. Acoust. Soc. Am.* 42, 1223–1231
/// (1967): c11 203, c12 53, c13 75, c14 9, c33 245, c44 60 GPa; e15 3.7, e22 2.5, e31 0.2,
/// e33 1.3 C/m²; ε11^S/ε0 44, ε33^S/ε0 29; ρ 4700 kg/m³.
pub fn lithium_niobate_warner_1967() -> Material {
    Material::trigonal_3m(
        "LiNbO3 (Warner, Onoe & Coquin 1967)",
        [203e9, 53e9, 75e9, 9e9, 245e9, 60e9],
        [3.7, 2.5, 0.2, 1.3],
        [44.0 * EPS0, 29.0 * EPS0],
        4700.0,
    )
    .expect("the tabulated LiNbO3 constants are valid")
}

/// Right-handed α-quartz, constants of R. Bechmann, "Elastic and piezoelectric constants of
/// alpha-quartz", *Phys. Rev.* 110, 1060–1061 (1958), as tabulated by A. J. Slobodnik et al.,
/// *Microwave Acoustics Handbook* vol. 1A (AFCRL-TR-73-0597, 1973): c11 86.74, c12 6.99,
/// c13 11.91, c14 −17.91, c33 107.2, c44 57.94 GPa; e11 0.171, e14 −0.0406 C/m²;
/// ε11^S 39.21 pF/m, ε33^S 41.03 pF/m; ρ 2651 kg/m³.
pub fn quartz_bechmann_1958() -> Material {
    Material::trigonal_32(
        "alpha-quartz (Bechmann 1958)",
        [86.74e9, 6.99e9, 11.91e9, -17.91e9, 107.2e9, 57.94e9],
        [0.171, -0.0406],
        [39.21e-12, 41.03e-12],
        2651.0,
    )
    .expect("the tabulated quartz constants are valid")
}
