//! Regenerates the numbers of `validation/static-contact/README.md`.
//!
//! ```sh
//! cargo run -p validation --release --example static_contact_report                 # every section (≈ 20 min, needs gmsh)
//! cargo run -p validation --release --example static_contact_report -- refinement   # one or more sections
//! ```
//! Sections: `single_post`, `stator`, `refinement`, `strip`, `high_preload`, `diameters`, `counts`. Results go to
//! `validation/static-contact/results/<section>.json` (override the folder with `--out DIR`) and
//! the force charts of the default scene to `validation/static-contact/figures/`. Meshes are made
//! with gmsh into the mesh cache (`gmsh_mesh::cache::meshes_dir`: `<cache>/meshes`, the cache being
//! `--cache`, `$SAWDRIVE_CACHE`, `$XDG_CACHE_HOME/sawdrive` or `~/.cache/sawdrive`).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use contact_springs::{Material, k_pn, k_sn};
use serde_json::{Value, json};
use static_contact::body::{BodyCompliance, BodySpec, Disk, TipLateral};
use static_contact::halfspace::disk_mutual_compliance;
use static_contact::mesh_source::{
    cache_dir, generate_mesh, resolve_mesh_verified, workspace_root,
};
use static_contact::output::write_force_chart;
use static_contact::params::{MeshSizes, StaticParams};
use static_contact::scene::{PostSite, StatorModel, StripModel};
use static_contact::{
    FitSample, PreloadResult, PreparedStrip, RunControl, StaticAnalysis, StaticReport, fit_eta,
    prepare_strip,
};

/// The static stage of `params`: the strip prepared, then analysed.
fn run(params: &StaticParams) -> static_contact::Result<StaticAnalysis> {
    let strip = prepare_strip(params)?;
    let report = strip.analyse(params, &params.post_springs()?, &RunControl::none())?;
    Ok(strip.into_analysis(params, report))
}

/// A strip model built here (not by [`prepare_strip`]) analysed with `params`.
fn analyse_built(
    model: StripModel,
    params: &StaticParams,
    springs: &contact_springs::PostSprings,
) -> static_contact::Result<(StripModel, StaticReport)> {
    let strip = PreparedStrip {
        model,
        mesh_file: String::new(),
        notes: Vec::new(),
        mesh_s: 0.0,
        condensation_s: 0.0,
    };
    let report = strip.analyse(params, springs, &RunControl::none())?;
    Ok((strip.model, report))
}

/// Preloads of the η-against-preload sweeps (N).
const SWEEP_N: [f64; 7] = [5.0, 10.0, 20.0, 40.0, 60.0, 80.0, 100.0];

type AnyResult<T> = Result<T, Box<dyn std::error::Error>>;

/// Fraction of the strip's length, centred, whose posts enter the "central" η fit that leaves
/// out the ends (where the rigid-punch edge effect loads the posts most). Default 0.6.
const CENTRAL_FRACTION: f64 = 0.6;

/// η fitted (docs/physics.md §6) on the posts of the central [`CENTRAL_FRACTION`] of the strip only,
/// each snapshot's load being what those posts carry in the FEM.
fn central_eta(report: &StaticReport, preload: &PreloadResult) -> Option<f64> {
    let xs = preload.snapshots[0].posts.iter().map(|q| q.x_m);
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    });
    let half_width = 0.5 * CENTRAL_FRACTION * (hi - lo);
    let centre = 0.5 * (lo + hi);
    let samples: Vec<FitSample> = preload
        .snapshots
        .iter()
        .map(|s| {
            let posts: Vec<_> = s
                .posts
                .iter()
                .filter(|q| (q.x_m - centre).abs() <= half_width)
                .collect();
            let force_n: Vec<f64> = posts.iter().map(|q| q.force_n).collect();
            FitSample {
                height_m: posts.iter().map(|q| q.surface_height_m).collect(),
                preload_n: force_n.iter().sum(),
                force_n,
            }
        })
        .collect();
    fit_eta(&samples, report.k_n_n_per_m).eta
}

/// 1 / (k_n (C_ii − C_ij)) for the strip's central post i and its neighbour j along x: the
/// stiffness ratio at which two neighbours in one contact patch split their load (their
/// equations (Cf)_i = δ − g_i, (Cf)_j = δ − g_j subtracted, the other loads acting alike).
fn two_post_patch_eta(model: &StripModel, k_n: f64) -> Option<f64> {
    let row: Vec<usize> = (0..model.posts.len())
        .filter(|&i| model.posts[i].row == 0)
        .collect();
    let (i, j) = (row[row.len() / 2], *row.get(row.len() / 2 + 1)?);
    let c = &model.compliance_m_per_n;
    // The wave is uniform in y: all strip rows at one x carry the same force, so sum over them.
    let column = |k: usize| -> f64 {
        let x = model.posts[k].x_m;
        let same_x = |q: &PostSite| (q.x_m - x).abs() < 1e-3 * model.config.pitch_m;
        (0..model.posts.len())
            .filter(|&m| same_x(&model.posts[m]))
            .map(|m| c[(i, m)])
            .sum()
    };
    Some(1.0 / (k_n * (column(i) - column(j))))
}

fn eta_table(report: &StaticReport) -> Vec<Value> {
    let mut rows: Vec<Value> = report
        .preloads
        .iter()
        .map(|p| {
            json!({
                "preload_n": p.preload_n,
                "eta": p.effective_contact_ratio,
                "eta_central": central_eta(report, p),
                "fit_relative_rms": p.eta_fit.relative_rms_residual,
                "load_sharing": p.load_sharing,
                "contact_fraction": p.contact_fraction,
                "flat_load_sharing": p.flat_stator.load_sharing,
                "complementarity_residual": p.complementarity_residual,
                "iterations": p.iterations,
            })
        })
        .collect();
    rows.sort_by(|a, b| {
        a["preload_n"]
            .as_f64()
            .unwrap_or(0.0)
            .total_cmp(&b["preload_n"].as_f64().unwrap_or(0.0))
    });
    rows
}

fn print_etas(label: &str, report: &StaticReport) {
    let mut preloads: Vec<_> = report.preloads.iter().collect();
    preloads.sort_by(|a, b| a.preload_n.total_cmp(&b.preload_n));
    let etas: Vec<String> = preloads
        .iter()
        .map(|p| {
            format!(
                "{}N:{} (central {})",
                p.preload_n,
                p.effective_contact_ratio
                    .map_or("-".into(), |e| format!("{e:.3}")),
                central_eta(report, p).map_or("-".into(), |e| format!("{e:.3}"))
            )
        })
        .collect();
    println!(
        "{label}: η {}  | full contact {} | flat load sharing {:.3} | slider {} nodes, condensation {:.1} s, total {:.1} s",
        etas.join(" "),
        report
            .eta_full_contact
            .map_or("-".into(), |e| format!("{e:.3}")),
        report.preloads[0].flat_stator.load_sharing,
        report.fem.slider.nodes,
        report.timings.condensation_s,
        report.timings.wall_time_s
    );
}

fn sweep(params: StaticParams) -> StaticParams {
    StaticParams {
        preload_n: 40.0,
        preload_sweep_n: SWEEP_N.to_vec(),
        ..params
    }
}

fn scene_json(name: &str, params: &StaticParams, analysis: &StaticAnalysis) -> Value {
    let report = &analysis.report;
    json!({
        "scene": name,
        "post_diameter_um": params.post_diameter_m * 1e6,
        "posts": params.posts_x * params.posts_y,
        "pitch_um": params.post_pitch_m * 1e6,
        "strip_posts": report.posts_in_strip,
        "strip_rows": params.strip_rows,
        "eta_full_contact": report.eta_full_contact,
        "eta_two_post_patch": two_post_patch_eta(&analysis.model, report.k_n_n_per_m),
        "element_order": params.element_order,
        "h_post_over_radius": params.mesh_sizes.h_post_over_radius,
        "stator": params.stator,
        "k_n_n_per_m": report.k_n_n_per_m,
        "slider_nodes": report.fem.slider.nodes,
        "timings": report.timings,
        "content_hash": report.content_hash,
        "eta_against_preload": eta_table(report),
    })
}

/// The paper's scenes at equal contact area, and the post-count study.
fn array_section(cases: &[(f64, usize)], figures: Option<&Path>) -> AnyResult<Value> {
    let mut out = Vec::new();
    for &(d, n) in cases {
        let params = sweep(StaticParams::square_array(d, n));
        let analysis = run(&params)?;
        let name = format!("d{:.0}um_{}x{}", d * 1e6, n, n);
        print_etas(&name, &analysis.report);
        if let Some(dir) = figures {
            let main = analysis
                .report
                .preloads
                .iter()
                .position(|p| p.preload_n == 40.0)
                .unwrap_or(0);
            write_force_chart(
                &analysis,
                main,
                0,
                &dir.join(format!("post_forces_{name}_40N")),
            )?;
            write_force_chart(
                &analysis,
                main,
                usize::MAX,
                &dir.join(format!("post_forces_{name}_40N_flat")),
            )?;
        }
        out.push(scene_json(&name, &params, &analysis));
    }
    Ok(Value::Array(out))
}

/// η on a 10-post strip of the default slider under mesh refinement.
fn refinement_section() -> AnyResult<Value> {
    let mut out = Vec::new();
    for (order, levels) in [(2u8, [1.0, 0.5, 0.25]), (1u8, [0.5, 0.25, 0.125])] {
        let mut etas = Vec::new();
        for h in levels {
            let params = StaticParams {
                strip_posts: Some(10),
                element_order: order,
                mesh_sizes: MeshSizes {
                    h_post_over_radius: h,
                    ..MeshSizes::default()
                },
                preload_n: 40.0,
                preload_sweep_n: vec![10.0, 100.0],
                ..StaticParams::default()
            };
            let analysis = run(&params)?;
            print_etas(
                &format!("Tet{} h_post = {h} a", if order == 2 { 10 } else { 4 }),
                &analysis.report,
            );
            etas.push((
                h,
                analysis
                    .report
                    .preloads
                    .iter()
                    .map(|p| (p.preload_n, p.effective_contact_ratio))
                    .collect::<Vec<_>>(),
                analysis.report.fem.slider.nodes,
            ));
        }
        // Observed order of convergence p = ln(|η1 − η2| / |η2 − η3|) / ln 2 per preload.
        let rates: Vec<Value> = (0..etas[0].1.len())
            .map(|k| {
                let e: Vec<f64> = etas.iter().map(|l| l.1[k].1.unwrap_or(f64::NAN)).collect();
                let p = ((e[0] - e[1]).abs() / (e[1] - e[2]).abs()).ln() / 2f64.ln();
                let extrapolated = e[2] + (e[2] - e[1]) / (2f64.powf(p) - 1.0);
                json!({ "preload_n": etas[0].1[k].0, "eta": e, "observed_order": p, "richardson_eta": extrapolated })
            })
            .collect();
        println!(
            "Tet{} rates: {}",
            if order == 2 { 10 } else { 4 },
            serde_json::to_string(&rates)?
        );
        out.push(json!({ "order": order, "h_post_over_radius": levels, "slider_nodes": etas.iter().map(|l| l.2).collect::<Vec<_>>(), "convergence": rates }));
    }
    Ok(Value::Array(out))
}

/// Half-space stator against the meshed stator block of the 10-post strip.
fn stator_section() -> AnyResult<Value> {
    let mut out = Vec::new();
    for h in [1.0, 0.5, 0.25] {
        let mut params = StaticParams {
            strip_posts: Some(10),
            stator: StatorModel::MeshedBlock,
            mesh_sizes: MeshSizes {
                h_post_over_radius: h,
                ..MeshSizes::default()
            },
            preload_sweep_n: vec![10.0, 100.0],
            ..StaticParams::default()
        };
        // The run's mesh: a Tet10 strip is the cached Tet4 file raised to Tet10 on reading.
        let mesh = resolve_mesh_verified(&params)?.read()?;
        let springs = params.post_springs()?;
        let meshed = StripModel::build(mesh.clone(), params.strip_config())?;
        let (meshed, meshed_report) = analyse_built(meshed, &params, &springs)?;
        params.stator = StatorModel::HalfSpace;
        let half = StripModel::build(mesh, params.strip_config())?;
        let (_, half_report) = analyse_built(half, &params, &springs)?;
        // The meshed block has symmetry planes in y (infinitely many rows) and rollers on its x
        // ends (mirror images in x), a clamped bottom 1 mm down. Compare differences C_55 − C_5j,
        // which do not depend on the loads' mean (it only shifts the approach): the half-space
        // sum over the same images converges for them.
        let s = meshed.stator.matrix();
        let stator = &params.stator_material;
        let a = 0.5 * params.post_diameter_m;
        let p = params.post_pitch_m;
        let length = 10.0 * p;
        let xs: Vec<f64> = meshed.posts.iter().map(|q| q.x_m).collect();
        let image_sum = |i: usize, j: usize| -> f64 {
            let mut sum = 0.0;
            for m in -2000i64..=2000 {
                for q in -40i64..=40 {
                    for xj in [
                        2.0 * q as f64 * length + xs[j],
                        2.0 * q as f64 * length - xs[j],
                    ] {
                        let r = (xs[i] - xj).hypot(m as f64 * p);
                        sum += disk_mutual_compliance(
                            stator.shear_modulus_pa,
                            stator.poisson_ratio,
                            a,
                            r,
                        );
                    }
                }
            }
            sum
        };
        let c55 = image_sum(5, 5);
        let rows: Vec<Value> = [4usize, 3, 0]
            .iter()
            .map(|&j| {
                let fem = s[(5, 5)] - s[(5, j)];
                let analytic = c55 - image_sum(5, j);
                json!({ "j": j, "fem_m_per_n": fem, "half_space_m_per_n": analytic, "ratio": fem / analytic })
            })
            .collect();
        println!(
            "stator h = {h} a: C55 − C5j meshed / half-space: {}",
            rows.iter()
                .map(|r| format!(
                    "j={} {:.4}",
                    r["j"],
                    r["ratio"].as_f64().unwrap_or(f64::NAN)
                ))
                .collect::<Vec<_>>()
                .join(", ")
        );
        print_etas("  meshed stator", &meshed_report);
        print_etas("  half-space stator", &half_report);
        out.push(json!({
            "h_post_over_radius": h,
            "stator_nodes": meshed_report.fem.stator.map(|s| s.nodes),
            "differential_compliance": rows,
            "eta_meshed": eta_table(&meshed_report),
            "eta_half_space": eta_table(&half_report),
        }));
    }
    Ok(Value::Array(out))
}

/// Strip width and length: the whole row (100 posts, 9.7 λ, with the slider's margins) one and
/// two pitches wide, and shorter strips without margins.
fn strip_section() -> AnyResult<Value> {
    let mut out = Vec::new();
    for (strip, rows) in [(None, 1), (None, 2), (Some(50), 1), (Some(25), 1)] {
        let params = StaticParams {
            strip_posts: strip,
            strip_rows: rows,
            preload_sweep_n: vec![10.0, 100.0],
            ..StaticParams::default()
        };
        let analysis = run(&params)?;
        let name = format!("strip_{}x{rows}", strip.unwrap_or(100));
        print_etas(&name, &analysis.report);
        out.push(scene_json(&name, &params, &analysis));
    }
    Ok(Value::Array(out))
}

/// The default scene at preloads high enough to bring (nearly) every post into contact.
fn high_preload_section() -> AnyResult<Value> {
    let params = StaticParams {
        preload_n: 40.0,
        preload_sweep_n: vec![150.0, 200.0, 300.0, 500.0],
        ..StaticParams::default()
    };
    let analysis = run(&params)?;
    print_etas("default scene, high preloads", &analysis.report);
    Ok(scene_json("d20um_100x100_high_preload", &params, &analysis))
}

/// The single-post springs under refinement of the quarter punch (R = 100 a, Tet10).
fn single_post_section() -> AnyResult<Value> {
    let a = 10e-6;
    let mut out = Vec::new();
    for h in [0.1, 0.05, 0.025] {
        let path =
            cache_dir(&StaticParams::default()).join(format!("punch-quarter_R100a_tet10_h{h}.msh"));
        if !path.is_file() {
            generate_mesh(
                "punch",
                &path,
                &[
                    ("a", a),
                    ("R_over_a", 100.0),
                    ("h_edge_over_a", h),
                    ("growth", 0.3),
                    ("sym", 2.0),
                    ("order", 2.0),
                ],
            )?;
        }
        let mesh = gmsh_mesh::read_msh(&path)?;
        let compliance = |material: &Material, lateral| -> AnyResult<f64> {
            let body = BodyCompliance::build(&BodySpec {
                name: "slider",
                mesh: &mesh,
                volume_group: "body".into(),
                material: elastic_fem::Material::isotropic(
                    material.youngs_modulus_pa(),
                    material.poisson_ratio,
                )?,
                contact_group: "punch".into(),
                disks: vec![Disk {
                    centre_m: [0.0; 3],
                    radius_m: a,
                }],
                lateral,
                clamped_groups: vec!["far_field".into()],
                roller_groups: vec![("sym_x0".into(), 0), ("sym_y0".into(), 1)],
                disk_fraction: 0.25,
                force_sign: 1.0,
            })?;
            Ok(body.compliance_m_per_n[(0, 0)])
        };
        let bonded = 1.0
            / (compliance(&Material::silicon(), TipLateral::Bonded)?
                * k_pn(&Material::silicon(), a)?);
        let free = 1.0
            / (compliance(&Material::lithium_niobate(), TipLateral::Free)?
                * k_sn(&Material::lithium_niobate(), a)?);
        println!(
            "punch h_edge = {h} a ({} nodes): k_FEM/k_pn = {bonded:.5}, k_FEM/k_sn = {free:.5}",
            mesh.nodes.len()
        );
        out.push(json!({ "h_edge_over_a": h, "nodes": mesh.nodes.len(), "bonded_over_k_pn": bonded, "frictionless_over_k_sn": free }));
    }
    println!(
        "(truncation at R = 100 a alone makes the model stiffer by ≈ 2a/(πR) = {:.4})",
        2.0 / (PI * 100.0)
    );
    Ok(Value::Array(out))
}

fn main() -> AnyResult<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let root = workspace_root();
    let mut out_dir = root.join("validation/static-contact/results");
    if let Some(i) = args.iter().position(|a| a == "--out") {
        out_dir = PathBuf::from(args.get(i + 1).ok_or("--out needs a directory")?);
        args.drain(i..=i + 1);
    }
    let figures = root.join("validation/static-contact/figures");
    std::fs::create_dir_all(&out_dir)?;
    std::fs::create_dir_all(&figures)?;
    let all = [
        "single_post",
        "stator",
        "refinement",
        "strip",
        "high_preload",
        "diameters",
        "counts",
    ];
    let sections: Vec<&str> = if args.is_empty() {
        all.to_vec()
    } else {
        args.iter().map(String::as_str).collect()
    };
    for section in sections {
        println!("== {section}");
        let value = match section {
            "single_post" => single_post_section()?,
            "stator" => stator_section()?,
            "refinement" => refinement_section()?,
            "strip" => strip_section()?,
            "high_preload" => high_preload_section()?,
            "diameters" => array_section(
                &[(20e-6, 100), (30e-6, 67), (40e-6, 50), (50e-6, 40)],
                Some(&figures),
            )?,
            "counts" => array_section(
                &[
                    (20e-6, 100),
                    (20e-6, 80),
                    (20e-6, 66),
                    (20e-6, 50),
                    (20e-6, 33),
                ],
                None,
            )?,
            other => {
                return Err(
                    format!("unknown section `{other}` (known: {})", all.join(", ")).into(),
                );
            }
        };
        // The case's figures are SVG (the chart writer draws a PNG copy too).
        validation::cases::drop_png_duplicates(&figures)?;
        let path = out_dir.join(format!("{section}.json"));
        std::fs::write(&path, serde_json::to_string_pretty(&value)? + "\n")?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
