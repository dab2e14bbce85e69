//! The MDR/Iwan spring bed against the closed forms it discretises: Hertz's force, Mindlin's
//! monotonic curve, the Mindlin–Deresiewicz unloading branch and loop energy, with the rate
//! of convergence under refinement.

use ball_slider::hertz::{self, HertzContact};
use ball_slider::mindlin::{MindlinContact, effective_shear_modulus_pa};
use ball_slider::{SpringBed, bearing_steel};
use contact_springs::Material;

const PRELOAD_N: f64 = 0.5;
const MU: f64 = 0.3;
const RADIUS_M: f64 = 1e-3;

fn contact() -> MindlinContact {
    let (ball, flat) = (bearing_steel(), Material::lithium_niobate());
    let h = HertzContact::new(
        RADIUS_M,
        hertz::effective_modulus_pa(&ball, &flat),
        PRELOAD_N,
    )
    .unwrap();
    MindlinContact::new(h, MU, effective_shear_modulus_pa(&ball, &flat)).unwrap()
}

/// A bed of n springs over 1.25 a (cell edges not aligned with the contact edge, as in the
/// dynamics).
fn bed(m: &MindlinContact, n: usize) -> SpringBed {
    SpringBed::sphere(
        RADIUS_M,
        1.25 * m.hertz.contact_radius_m,
        n,
        m.hertz.effective_modulus_pa,
        m.effective_shear_modulus_pa,
        MU,
    )
}

/// Mindlin's Q(δ_t) = μN[1 − (1 − δ_t/C)^{3/2}], the inverse of δ_t(Q).
fn mindlin_force(m: &MindlinContact, u: f64) -> f64 {
    m.friction_limit_n() * (1.0 - (1.0 - u / m.full_slip_displacement_m()).max(0.0).powf(1.5))
}

/// Largest |Q_bed − Q_Mindlin|/μN along a monotonic loading to 0.98 C in 200 increments.
fn monotonic_error(m: &MindlinContact, n: usize) -> f64 {
    let mut b = bed(m, n);
    let d = m.hertz.approach_m;
    let du = 0.98 * m.full_slip_displacement_m() / 200.0;
    (1..=200)
        .map(|j| {
            b.commit(d, du);
            (b.force() - mindlin_force(m, j as f64 * du)).abs() / m.friction_limit_n()
        })
        .fold(0.0, f64::max)
}

fn order(errors: &[f64]) -> f64 {
    let k = errors.len();
    (errors[k - 2] / errors[k - 1]).log2()
}

#[test]
fn bed_normal_force_converges_to_hertz() {
    let m = contact();
    let errs: Vec<f64> = [50, 100, 200, 400]
        .iter()
        .map(|&n| (bed(&m, n).normal_force(m.hertz.approach_m) / PRELOAD_N - 1.0).abs())
        .collect();
    assert!(
        errs[3] < 2e-5,
        "bed normal force at 400 springs: rel. error {}",
        errs[3]
    );
    assert!(
        errs.windows(2).all(|w| w[1] < w[0]),
        "normal force error must fall: {errs:?}"
    );
}

#[test]
fn bed_reproduces_mindlin_curve_with_second_order_convergence() {
    let m = contact();
    let errs: Vec<f64> = [50, 100, 200, 400]
        .iter()
        .map(|&n| monotonic_error(&m, n))
        .collect();
    let p = order(&errs);
    assert!(
        errs[2] < 2e-4,
        "Mindlin curve at 200 springs: max |ΔQ|/μN = {}",
        errs[2]
    );
    assert!(
        p > 1.6,
        "convergence order of the Mindlin curve {p} (errors {errs:?})"
    );
}

/// Load to +u*, then cycle −u* → +u* in `steps` increments per leg; returns the bed's
/// force at each increment of the unloading leg and the dissipation of the closed cycle.
fn cycle(m: &MindlinContact, n: usize, u_star: f64, steps: usize) -> (Vec<(f64, f64)>, f64) {
    let mut b = bed(m, n);
    let d = m.hertz.approach_m;
    b.commit(d, u_star);
    let du = 2.0 * u_star / steps as f64;
    let mut unloading = Vec::new();
    let mut dissipation = 0.0;
    for j in 1..=steps {
        dissipation += b.commit(d, -du).dissipation;
        unloading.push((u_star - j as f64 * du, b.force()));
    }
    for _ in 0..steps {
        dissipation += b.commit(d, du).dissipation;
    }
    (unloading, dissipation)
}

#[test]
fn bed_unloading_branch_follows_the_mindlin_deresiewicz_rule() {
    let m = contact();
    let q_star = 0.7 * m.friction_limit_n();
    let u_star = m.compliance_m(q_star).unwrap();
    let (unloading, _) = cycle(&m, 400, u_star, 200);
    let worst = unloading
        .iter()
        .map(|&(u, q)| {
            (m.unloading_m(q_star, q.clamp(-q_star, q_star)).unwrap() - u).abs() / u_star
        })
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-3,
        "unloading branch δ_U(Q_bed) − δ: worst {worst} of δ(Q*)"
    );
}

#[test]
fn bed_loop_energy_converges_to_mindlin_deresiewicz() {
    let m = contact();
    for q in [0.3, 0.8] {
        let q_star = q * m.friction_limit_n();
        let u_star = m.compliance_m(q_star).unwrap();
        let closed = m.loop_energy_j(q_star).unwrap();
        let errs: Vec<f64> = [50, 100, 200, 400]
            .iter()
            .map(|&n| (cycle(&m, n, u_star, 400).1 / closed - 1.0).abs())
            .collect();
        assert!(
            errs[3] < 1e-3,
            "loop energy at Q*/μN = {q}, 400 springs: rel. error {}",
            errs[3]
        );
        assert!(
            errs[3] < errs[0] / 8.0,
            "loop energy error must fall with refinement: {errs:?}"
        );
    }
}

#[test]
fn bed_forgets_its_memory_when_the_contact_lifts_off() {
    let m = contact();
    let mut b = bed(&m, 100);
    b.commit(m.hertz.approach_m, 0.5 * m.full_slip_displacement_m());
    assert!(b.force() > 0.0 && b.energy() > 0.0);
    let step = b.commit(-1e-9, 0.0);
    assert_eq!(b.force(), 0.0, "tangential force after lift-off");
    assert_eq!(step.in_contact, 0);
    assert!(
        step.dissipation > 0.0 && (step.dissipation + step.energy_change).abs() < 1e-18,
        "released energy is dissipated"
    );
}
