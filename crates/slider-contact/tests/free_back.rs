//! The free back (pressure and point preload mechanisms) through the whole stage: its limits
//! and the sign of the plate's bending.

use contact_springs::Material;
use slider_contact::{CgOptions, Mechanism, SliderModel, SliderParams};

/// A 20 × 20 post slider without margins on a flat stator, 4 mN per post.
fn flat(mechanism: Mechanism, slider_material: Material, thickness_m: f64) -> SliderParams {
    SliderParams {
        posts_x: 20,
        posts_y: 20,
        slider_length_m: 20.0 * 40e-6,
        slider_width_m: 20.0 * 40e-6,
        slider_thickness_m: thickness_m,
        wave_amplitude_m: 0.0,
        preload_n: 400.0 * 4e-3,
        mechanism,
        slider_material,
        ..SliderParams::default()
    }
}

#[test]
fn a_stiff_free_back_under_pressure_reproduces_the_rigid_back() {
    // A body 1000× stiffer than Si: the plate's bending vanishes, and on a flat stator with a
    // centred load the rigid back's moments vanish by symmetry — both mechanisms are one punch.
    let stiff = Material {
        shear_modulus_pa: 1e3 * Material::silicon().shear_modulus_pa,
        ..Material::silicon()
    };
    let rigid = SliderModel::build(&flat(Mechanism::Rigid, stiff.clone(), 0.5e-3))
        .unwrap()
        .solve_phase(1.6, None)
        .unwrap();
    let free = SliderModel::build(&flat(Mechanism::Pressure, stiff, 0.5e-3))
        .unwrap()
        .solve_phase(1.6, None)
        .unwrap();
    let max = rigid.force_n.iter().copied().fold(0.0, f64::max);
    for (k, (a, b)) in rigid.force_n.iter().zip(&free.force_n).enumerate() {
        assert!(
            (a - b).abs() < 2e-3 * max,
            "post {k}: force under a rigid back {a} vs a stiff free back under pressure {b}"
        );
    }
}

#[test]
fn a_thin_free_back_under_pressure_spreads_the_load_more_evenly_than_a_rigid_back() {
    // The rigid punch loads its edges (stator half-space); a thin plate under pressure follows
    // the stator's deflection and evens the post forces out: higher load sharing.
    let si = Material::silicon();
    let rigid = SliderModel::build(&flat(Mechanism::Rigid, si.clone(), 0.1e-3))
        .unwrap()
        .solve_phase(1.6, None)
        .unwrap();
    let free = SliderModel::build(&flat(Mechanism::Pressure, si, 0.1e-3))
        .unwrap()
        .solve_phase(1.6, None)
        .unwrap();
    assert!(
        free.load_sharing > rigid.load_sharing + 0.01,
        "load sharing: free back under pressure {} vs rigid back {}",
        free.load_sharing,
        rigid.load_sharing
    );
    let sum: f64 = free.force_n.iter().sum();
    assert!((sum - 1.6).abs() < 1e-9, "total post force {sum} N");
}

#[test]
fn a_ball_off_centre_shifts_the_load_towards_it_and_balances_its_moment() {
    let si = Material::silicon();
    let (x, y) = (0.3e-3, 0.45e-3);
    let params = flat(Mechanism::Point { x_m: x, y_m: y }, si, 0.1e-3);
    let g = params.geometry();
    let s = SliderModel::build(&params)
        .unwrap()
        .solve_phase(1.6, None)
        .unwrap();
    let (mut mx, mut my) = (0.0, 0.0);
    for i in 0..g.posts_x {
        for j in 0..g.posts_y {
            let f = s.force_n[g.index(i, j)];
            mx += f * (g.x_m(i) - x);
            my += f * (g.y_m(j) - y);
        }
    }
    assert!(
        mx.abs() < 1e-9 * 1.6 * 1e-3 && my.abs() < 1e-9 * 1.6 * 1e-3,
        "moments of the post forces about the ball: {mx:e}, {my:e} N·m"
    );
    let near = s.force_n[g.index(7, 11)];
    let far = s.force_n[g.index(19, 0)];
    assert!(
        near > far,
        "post force next to the ball {near} N must exceed the far corner's {far} N"
    );
}

#[test]
fn the_plate_preconditioned_ball_solve_gives_the_plain_solution_in_fewer_iterations() {
    // A 30 × 30 post slider of thin Si (0.1 mm) with margins, a ball off-centre, on the wave.
    let params = SliderParams {
        posts_x: 30,
        posts_y: 30,
        slider_length_m: 30.0 * 40e-6 + 0.2e-3,
        slider_width_m: 30.0 * 40e-6 + 0.2e-3,
        slider_thickness_m: 0.1e-3,
        preload_n: 900.0 * 4e-3,
        mechanism: Mechanism::Point {
            x_m: 0.6e-3,
            y_m: 0.7e-3,
        },
        // Both solves to 1e-9 (tighter than the default) to compare them to 1e-7 of P/N.
        solver: CgOptions {
            tolerance: 1e-9,
            ..CgOptions::default()
        },
        ..SliderParams::default()
    };
    let mut model = SliderModel::build(&params).unwrap();
    let plain = model.solve_phase(params.preload_n, Some(0.3)).unwrap();
    model.precondition_free_back = true;
    let pre = model.solve_phase(params.preload_n, Some(0.3)).unwrap();
    let mean = params.preload_n / 900.0;
    for (k, (a, b)) in plain.force_n.iter().zip(&pre.force_n).enumerate() {
        assert!(
            (a - b).abs() < 1e-7 * mean,
            "post force {k}: preconditioned {b:.6e} N vs plain {a:.6e} N"
        );
    }
    println!(
        "CG iterations: plain {}, preconditioned {}",
        plain.iterations, pre.iterations
    );
    assert!(
        pre.iterations < plain.iterations,
        "CG iterations: preconditioned {} vs plain {}",
        pre.iterations,
        plain.iterations
    );
}
