//! The closed-form power flux against an independent numerical depth integration.
//!
//! For a lossless guided wave the time-averaged power per unit width equals the energy velocity
//! times the time-averaged energy per unit area, and the energy velocity equals the group
//! velocity (M. A. Biot, *Phys. Rev.* 105, 1129 (1957); B. A. Auld, *Acoustic Fields and Waves in
//! Solids* II, §10.F), which for the non-dispersive half-space wave is the phase velocity:
//! P_crystal + P_vacuum = v·(W_crystal + W_vacuum). The energy densities (kinetic ¼ρω²|u|², strain
//! ¼Re(S*·T), electric ¼Re(E*·D), vacuum ¼ε0|∇φ|²) are built here from the partial waves and the
//! rotated constants and integrated over depth by composite Simpson's rule. The Poynting vector
//! is integrated the same way, part by part, to check the closed-form depth integrals.

use saw_wave::{C64, Cut, EulerAngles, Material, SurfaceMode, VACUUM_PERMITTIVITY_F_PER_M};
use std::f64::consts::PI;

const FREQUENCY_HZ: f64 = 9.61e6;
/// Simpson intervals over the integration depth.
const INTERVALS: usize = 200_000;
/// Integration depth in slowest decay lengths 1/(k·min Im p) (the integrand falls as e^(−2·this)).
const DECAY_LENGTHS: f64 = 20.0;

/// Time-averaged densities at one depth for u_z(0) = 1 m (every quantity scales with |u_z(0)|²).
struct Densities {
    energy_j_per_m3: f64,
    poynting_mechanical_w_per_m2: f64,
    poynting_electrical_w_per_m2: f64,
}

fn voigt(i: usize, j: usize) -> usize {
    match (i.min(j), i.max(j)) {
        (0, 0) => 0,
        (1, 1) => 1,
        (2, 2) => 2,
        (1, 2) => 3,
        (0, 2) => 4,
        _ => 5,
    }
}

fn densities(mode: &SurfaceMode, m: &Material, depth_m: f64) -> Densities {
    let omega = 2.0 * PI * FREQUENCY_HZ;
    let k = omega / mode.phase_velocity_m_per_s;
    let j = C64::new(0.0, 1.0);
    // Generalized displacement U = (u1, u2, u3, φ) and its x1, x3 derivatives.
    let (mut u, mut d1, mut d3) = (
        [C64::new(0.0, 0.0); 4],
        [C64::new(0.0, 0.0); 4],
        [C64::new(0.0, 0.0); 4],
    );
    for wave in &mode.partial_waves {
        let e = (j * k * wave.p() * depth_m).exp();
        for (i, f) in wave.fields().into_iter().enumerate() {
            u[i] += f * e;
            d1[i] += -j * k * f * e;
            d3[i] += -j * k * wave.p() * f * e;
        }
    }
    let grad = |comp: usize, axis: usize| match axis {
        0 => d1[comp],
        2 => d3[comp],
        _ => C64::new(0.0, 0.0),
    };
    let mut strain = [C64::new(0.0, 0.0); 6];
    for a in 0..3 {
        for b in a..3 {
            strain[voigt(a, b)] = if a == b {
                grad(a, a)
            } else {
                grad(a, b) + grad(b, a)
            };
        }
    }
    let field = [-grad(3, 0), C64::new(0.0, 0.0), -grad(3, 2)];
    let mut stress = [C64::new(0.0, 0.0); 6];
    for (i, s) in stress.iter_mut().enumerate() {
        *s = (0..6)
            .map(|jj| strain[jj] * m.stiffness_pa[i][jj])
            .sum::<C64>()
            - (0..3)
                .map(|kk| field[kk] * m.piezo_c_per_m2[kk][i])
                .sum::<C64>();
    }
    let mut displacement_d = [C64::new(0.0, 0.0); 3];
    for (i, dd) in displacement_d.iter_mut().enumerate() {
        *dd = (0..6)
            .map(|jj| strain[jj] * m.piezo_c_per_m2[i][jj])
            .sum::<C64>()
            + (0..3)
                .map(|kk| field[kk] * m.permittivity_f_per_m[i][kk])
                .sum::<C64>();
    }
    let kinetic =
        0.25 * m.density_kg_per_m3 * omega * omega * (0..3).map(|i| u[i].norm_sqr()).sum::<f64>();
    let strain_energy = 0.25
        * (0..6)
            .map(|i| (strain[i].conj() * stress[i]).re)
            .sum::<f64>();
    let electric = 0.25
        * (0..3)
            .map(|i| (field[i].conj() * displacement_d[i]).re)
            .sum::<f64>();
    // P1 = −½Re(T_1j v_j*) + ½Re(φ (jωD_1)*), v = jωu.
    let t1 = [stress[0], stress[5], stress[4]];
    let mechanical = -0.5
        * (0..3)
            .map(|i| (t1[i] * (j * omega * u[i]).conj()).re)
            .sum::<f64>();
    let electrical = 0.5 * (u[3] * (j * omega * displacement_d[0]).conj()).re;
    Densities {
        energy_j_per_m3: kinetic + strain_energy + electric,
        poynting_mechanical_w_per_m2: mechanical,
        poynting_electrical_w_per_m2: electrical,
    }
}

/// Composite Simpson integral of `f` over [0, length].
fn simpson(length: f64, mut f: impl FnMut(f64) -> [f64; 3]) -> [f64; 3] {
    let h = length / INTERVALS as f64;
    let mut sum = [0.0; 3];
    for i in 0..=INTERVALS {
        let w = if i == 0 || i == INTERVALS {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        let v = f(i as f64 * h);
        for (s, x) in sum.iter_mut().zip(v) {
            *s += w * x;
        }
    }
    sum.map(|s| s * h / 3.0)
}

struct Check {
    /// |P_closed − v·W| / P_closed.
    energy_velocity: f64,
    /// |P_closed − ∫P| / P_closed for the mechanical and the electrical crystal parts.
    mechanical: f64,
    electrical: f64,
}

fn check(mode: &SurfaceMode, rotated: &Material) -> Check {
    let v = mode.phase_velocity_m_per_s;
    let k = 2.0 * PI * FREQUENCY_HZ / v;
    let slowest = mode
        .partial_waves
        .iter()
        .map(|w| w.p().im)
        .fold(f64::INFINITY, f64::min);
    let depth = DECAY_LENGTHS / (k * slowest);
    let [w_crystal, p_mech, p_elec] = simpson(depth, |d| {
        let dens = densities(mode, rotated, d);
        [
            dens.energy_j_per_m3,
            dens.poynting_mechanical_w_per_m2,
            dens.poynting_electrical_w_per_m2,
        ]
    });
    // Vacuum: φ = φ0 e^(−kz), ¼ε0|∇φ|² = ½ε0k²|φ0|²e^(−2kz), integrated numerically as well.
    let phi0 = mode.fields_at_depth(0.0).phi_v_per_m.norm();
    let [w_vacuum, _, _] = simpson(DECAY_LENGTHS / k, |z| {
        [
            0.5 * VACUUM_PERMITTIVITY_F_PER_M * k * k * phi0 * phi0 * (-2.0 * k * z).exp(),
            0.0,
            0.0,
        ]
    });
    let flux = mode.power_flux;
    let closed = flux.total_w_per_m_per_m2_per_hz() * FREQUENCY_HZ;
    let mech_closed = flux.mechanical_w_per_m_per_m2_per_hz * FREQUENCY_HZ;
    let elec_closed = flux.electrical_crystal_w_per_m_per_m2_per_hz * FREQUENCY_HZ;
    Check {
        energy_velocity: ((closed - v * (w_crystal + w_vacuum)) / closed).abs(),
        mechanical: ((mech_closed - p_mech) / closed).abs(),
        electrical: ((elec_closed - p_elec) / closed).abs(),
    }
}

fn assert_power_consistent(cut: &Cut) {
    let wave = cut.solve().unwrap();
    let rotated = cut.rotated_material();
    for mode in [&wave.free, &wave.metallized] {
        let c = check(mode, &rotated);
        let what = format!("{} ({} surface)", cut.name, mode.surface);
        assert!(
            c.energy_velocity < 1e-10,
            "{what}: power flux vs energy velocity × energy differ by {:e}",
            c.energy_velocity
        );
        assert!(
            c.mechanical < 1e-10,
            "{what}: closed-form mechanical flux vs numerical Poynting integral differ by {:e}",
            c.mechanical
        );
        assert!(
            c.electrical < 1e-10,
            "{what}: closed-form electrical flux vs numerical Poynting integral differ by {:e}",
            c.electrical
        );
    }
}

#[test]
fn power_flux_equals_phase_velocity_times_energy_for_128yx_linbo3() {
    assert_power_consistent(&Cut::from_name("128yx-linbo3").unwrap());
}

#[test]
fn power_flux_equals_phase_velocity_times_energy_for_yz_linbo3() {
    assert_power_consistent(&Cut::from_name("yz-linbo3").unwrap());
}

#[test]
fn power_flux_equals_phase_velocity_times_energy_for_st_x_quartz() {
    assert_power_consistent(&Cut::from_name("st-x-quartz").unwrap());
}

#[test]
fn power_flux_equals_phase_velocity_times_energy_for_an_isotropic_solid() {
    let solid = Material::isotropic("isotropic test solid", 45e9, 30e9, 2700.0, 4.0).unwrap();
    assert_power_consistent(&Cut::new(
        "isotropic",
        solid,
        EulerAngles::new(0.0, 0.0, 0.0),
    ));
}
