//! The default slider (100 × 100 posts, rigid back, no scatter) at 10, 40 and 100 N: η, contact
//! fraction, load sharing, CG iterations and wall times.
//!
//! `cargo run -p slider-contact --profile test --example default_slider [posts_per_side]
//! [rigid | pressure | point] [precondition | plain] [tolerance] [phases]` (point: a ball at the
//! slider's centre; `precondition`: the ball's CG preconditioned by the plate,
//! `SliderModel::precondition_free_back`; tolerance: the CG's, default 1e-9; phases: wave phases
//! per preload, default 4).

use slider_contact::{ComplianceOperator, Mechanism, MechanismExt, SliderModel, SliderParams};

fn main() -> anyhow::Result<()> {
    let side: usize = std::env::args().nth(1).map_or(Ok(100), |s| s.parse())?;
    let name = std::env::args().nth(2).unwrap_or_else(|| "rigid".into());
    let point = (name == "point").then_some((2.5e-3, 2.5e-3));
    let mechanism = Mechanism::parse(&name, point)?;
    // A square array of side² posts of 20 µm in the default 4 × 4 mm area (side < 200).
    let params = SliderParams {
        posts_x: side,
        posts_y: side,
        post_pitch_m: 4e-3 / side as f64,
        mechanism,
        ..SliderParams::default()
    };
    let mut params = params;
    if let Some(tol) = std::env::args().nth(4) {
        params.solver.tolerance = tol.parse()?;
    }
    if let Some(phases) = std::env::args().nth(5) {
        params.phases = phases.parse()?;
    }
    let mut model = SliderModel::build(&params)?;
    model.precondition_free_back = std::env::args().nth(3).as_deref() == Some("precondition");
    println!(
        "operator build: {:.3} s, diagonal {:?}",
        model.build_s,
        model.operator.parts()
    );
    let t = std::time::Instant::now();
    let s = model.solve_phase(40.0, Some(0.0))?;
    println!(
        "one phase at 40 N: {:.3} s, {} iterations",
        t.elapsed().as_secs_f64(),
        s.iterations
    );
    let f = vec![1e-3; model.operator.len()];
    let mut u = vec![0.0; f.len()];
    let t = std::time::Instant::now();
    for _ in 0..20 {
        model.operator.apply(&f, &mut u);
    }
    println!("one C·f: {:.2} ms", t.elapsed().as_secs_f64() / 20.0 * 1e3);
    if name != "rigid" {
        // The free back: the stage at 40 N only (4 phases and η).
        let r = model.analyse(40.0)?;
        println!(
            "{name}: P = 40 N, {} phases + η: {:.3} s, η = {:?} (misfit {:.4}), contact fraction {:.3}, load sharing {:.3}, CG iterations {:?}",
            params.phases,
            r.contact_s,
            r.effective_contact_ratio,
            r.eta_fit.relative_rms_residual,
            r.contact_fraction,
            r.load_sharing,
            r.snapshots.iter().map(|s| s.iterations).collect::<Vec<_>>()
        );
        return Ok(());
    }
    let flat = model.solve_phase(40.0, None)?;
    let f = &flat.force_n;
    let (lo, hi) = f
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    println!(
        "flat stator, 40 N: load sharing {:.4}, post force min/mean/max {:.3e} / {:.3e} / {:.3e} N ({} iterations)",
        flat.load_sharing,
        lo,
        40.0 / f.len() as f64,
        hi,
        flat.iterations
    );
    for preload in [10.0, 40.0, 100.0] {
        let r = model.analyse(preload)?;
        let its: Vec<usize> = r.snapshots.iter().map(|s| s.iterations).collect();
        println!(
            "P = {preload:5.1} N: η = {:?}, contact fraction {:.3}, load sharing {:.3}, residual {:.1e}, CG iterations {:?}, contact {:.3} s",
            r.effective_contact_ratio,
            r.contact_fraction,
            r.load_sharing,
            r.complementarity_residual,
            its,
            r.contact_s
        );
    }
    Ok(())
}
