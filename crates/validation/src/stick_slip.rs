//! Validation study of the `stick-slip` crate (`sawdrive validate stick-slip`, or
//! `cargo run -p validation --example validate_stick_slip --release`): work-precision of every
//! integrator against the closed-form event-driven post, stability maps of the fixed-step
//! schemes, transient-vs-period-average agreement, the paper's trends (Figs 7–12) and the Fig. 6
//! history (docs/physics.md §4–5); charts plus `report.json` in the output directory. Valid for the
//! paper's motor (docs/physics.md §1) with the springs and post mass given in [`ValidationSetup`].

use std::path::{Path, PathBuf};
use std::time::Instant;

use charts::{CategoryMap, Chart, Scale, Series, Style, write_category_map, write_stacked};
use contact_springs::{Material, post_springs};
use serde::Serialize;

use stick_slip::plots::{
    write_post_history_chart, write_slider_history_chart, write_speed_thrust_comparison,
};
use stick_slip::{
    DynamicResult, DynamicScene, Integrator, ModelChoice, ModelKind, PAPER_FRICTION_COEFFICIENT,
    PeriodicAverageModel, PostContact, PostLayout, StabilityPolicy, StabilityProbe, TransientModel,
    TransientStart, VerticalModel,
};

use crate::error::ValidationError;

type Result<T> = std::result::Result<T, ValidationError>;

/// Accuracy class boundary of the stability maps: a stable cell within this relative error of
/// its row's finest stable result counts as accurate. Default 0.02.
const MAP_ACCURACY: f64 = 0.02;
/// Wave periods run per stability-map cell. Default 4.
const MAP_PERIODS: usize = 4;
/// Regularisation speed of the work-precision chart's explicit scheme (m/s). Default 0.1.
const WORK_PRECISION_REGULARIZATION_M_PER_S: f64 = 0.1;
/// Repetitions of the (fast) event-driven reference to time it. Default 20.
const REFERENCE_REPEATS: usize = 20;
/// Largest number of timing repetitions of one work-precision point. Default 5.
const TIMING_REPEATS: usize = 5;
/// Runs shorter than this (s) are repeated for timing. Default 0.05.
const REPEAT_BELOW_S: f64 = 0.05;

/// What the study needs from outside the crate: the post springs (from Johnson's formulas) and
/// mass, for the paper's 20 µm posts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValidationSetup {
    /// Normal post stiffness (N/m).
    pub k_n_n_per_m: f64,
    /// Tangential post stiffness (N/m).
    pub k_t_n_per_m: f64,
    /// Post mass (kg).
    pub post_mass_kg: f64,
    /// Springs of the 50 µm post (N/m), for the diameter comparison.
    pub k_n_50um_n_per_m: f64,
    /// Tangential springs of the 50 µm post (N/m).
    pub k_t_50um_n_per_m: f64,
    /// How much to compute.
    pub level: ValidationLevel,
}

/// Radius (m) of the paper's 20 µm post, for which the study is set up.
pub const PAPER_POST_RADIUS_M: f64 = 0.5 * motor::paper::POST_DIAMETER_M;
/// Radius (m) of the 50 µm post of the diameter comparison.
pub const WIDE_POST_RADIUS_M: f64 = 25e-6;
/// Post height (m), docs/physics.md §1.
pub const PAPER_POST_HEIGHT_M: f64 = motor::paper::POST_HEIGHT_M;

impl ValidationSetup {
    /// The study for the paper's posts: Johnson springs of Si posts on LiNbO3
    /// (`contact_springs::post_springs`) of radius [`PAPER_POST_RADIUS_M`] and
    /// [`WIDE_POST_RADIUS_M`], and the mass ρπa²h of the 20 µm post.
    pub fn paper_posts(level: ValidationLevel) -> Result<Self> {
        let (si, linbo3) = (Material::silicon(), Material::lithium_niobate());
        let springs = |a| {
            post_springs(&si, &linbo3, a).map_err(|source| ValidationError::Formula {
                spring: "post springs (Si on LiNbO3)",
                source,
            })
        };
        let (narrow, wide) = (springs(PAPER_POST_RADIUS_M)?, springs(WIDE_POST_RADIUS_M)?);
        Ok(Self {
            k_n_n_per_m: narrow.k_n_n_per_m,
            k_t_n_per_m: narrow.k_t_n_per_m,
            post_mass_kg: PostContact::cylinder_mass_kg(
                si.density_kg_per_m3,
                PAPER_POST_RADIUS_M,
                PAPER_POST_HEIGHT_M,
            ),
            k_n_50um_n_per_m: wide.k_n_n_per_m,
            k_t_50um_n_per_m: wide.k_t_n_per_m,
            level,
        })
    }
}

/// Size of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValidationLevel {
    /// Tiny grids, short transients: checks that every figure is produced (tests, ≈ 2 s).
    Smoke,
    /// Coarser grids and shorter transients (≈ 10 s in release).
    Quick,
    /// The figures kept in validation/stick-slip (≈ 1–2 min in release).
    Full,
}

impl ValidationLevel {
    /// Pick by level.
    fn pick<T>(self, smoke: T, quick: T, full: T) -> T {
        match self {
            Self::Smoke => smoke,
            Self::Quick => quick,
            Self::Full => full,
        }
    }
}

/// One point of the work-precision chart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WorkPrecisionPoint {
    /// Integrator name.
    pub scheme: String,
    /// Steps per wave period T/dt (0 for the closed-form scheme).
    pub steps_per_period: f64,
    /// Wall time for stall thrust plus no-load speed (s).
    pub wall_time_s: f64,
    /// Stall thrust (N).
    pub stall_thrust_n: f64,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: f64,
    /// Relative error of the stall thrust against the closed-form reference.
    pub stall_error: f64,
    /// Relative error of the no-load speed against the closed-form reference.
    pub no_load_error: f64,
}

/// A stability map over step size × a second parameter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityMapReport {
    /// Integrator name.
    pub scheme: String,
    /// dt/T of the columns.
    pub step_over_period: Vec<f64>,
    /// Second parameter of the rows (name in `parameter`).
    pub values: Vec<f64>,
    /// Row parameter name with unit.
    pub parameter: String,
    /// `cells[row][column]`: index into `categories`.
    pub cells: Vec<Vec<usize>>,
    /// Category names.
    pub categories: Vec<String>,
    /// Theoretical largest stable dt/T of every row.
    pub theoretical_limit_over_period: Vec<f64>,
}

/// Transient versus period average on the paper scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AgreementReport {
    /// Loads compared (N).
    pub loads_n: Vec<f64>,
    /// Period-average speeds (m/s).
    pub periodic_speed_m_per_s: Vec<f64>,
    /// Transient speeds (m/s).
    pub transient_speed_m_per_s: Vec<f64>,
    /// Largest relative speed difference.
    pub max_speed_difference: f64,
    /// Period-average and transient stall thrust (N).
    pub stall_thrust_n: (f64, f64),
    /// Period-average and transient no-load speed (m/s).
    pub no_load_speed_m_per_s: (f64, f64),
    /// Transient wall time for the full solve (s).
    pub transient_wall_time_s: f64,
    /// Incommensurate 33 × 33 at 121 µm: period-average and transient no-load speed (m/s).
    pub incommensurate_no_load_m_per_s: (f64, f64),
    /// Burst of 20 periods: displacement (m) and peak speed (m/s).
    pub burst_displacement_m: f64,
    /// Peak speed during the burst (m/s).
    pub burst_peak_speed_m_per_s: f64,
}

/// One trend curve: a quantity against preload.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrendCurve {
    /// Label (post count or diameter).
    pub label: String,
    /// Preloads (N).
    pub preload_n: Vec<f64>,
    /// Stall thrust (N).
    pub stall_thrust_n: Vec<f64>,
    /// No-load speed (m/s).
    pub no_load_speed_m_per_s: Vec<f64>,
}

/// Everything the study measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValidationReport {
    /// Closed-form stall thrust (N) of the paper scene at 40 N.
    pub reference_stall_thrust_n: f64,
    /// Closed-form no-load speed (m/s).
    pub reference_no_load_speed_m_per_s: f64,
    /// Wall time of the closed-form stall + no-load speed (s).
    pub reference_wall_time_s: f64,
    /// Work-precision points of every scheme.
    pub work_precision: Vec<WorkPrecisionPoint>,
    /// Observed order of the return mapping (stall, no-load): least-squares slope.
    pub return_mapping_order: (f64, f64),
    /// Converged values of the schemes with post mass (finest step): stall thrust (N) and
    /// no-load speed (m/s) of `post-mass` and `regularized-explicit` — the model floor against
    /// the massless reference.
    pub mass_model_values: Vec<(String, f64, f64)>,
    /// Stability maps.
    pub stability_maps: Vec<StabilityMapReport>,
    /// Transient agreement.
    pub agreement: AgreementReport,
    /// Trend curves (post count and diameter).
    pub trends: Vec<TrendCurve>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

fn paper_scene(setup: &ValidationSetup) -> DynamicScene {
    let mut scene = DynamicScene::paper_default(setup.k_n_n_per_m, setup.k_t_n_per_m);
    scene.contact = PostContact::new(
        setup.k_n_n_per_m,
        setup.k_t_n_per_m,
        PAPER_FRICTION_COEFFICIENT,
    )
    .with_post_mass(setup.post_mass_kg);
    scene.model = ModelChoice::PeriodicAverage;
    scene
}

fn chart_error(stem: &Path) -> impl FnOnce(charts::ChartError) -> ValidationError + '_ {
    move |source| ValidationError::Chart {
        path: stem.to_path_buf(),
        source,
    }
}

/// Run the whole study, writing charts and `report.json` into `out_dir`.
pub fn run_validation(setup: &ValidationSetup, out_dir: &Path) -> Result<ValidationReport> {
    std::fs::create_dir_all(out_dir).map_err(|source| ValidationError::Io {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let mut files = Vec::new();
    let scene = paper_scene(setup);
    // Reference: closed-form event-driven post.
    let reference = PeriodicAverageModel::new(&scene)?;
    let started = Instant::now();
    let (mut stall, mut v0) = (0.0, 0.0);
    for _ in 0..REFERENCE_REPEATS {
        stall = reference.stall_thrust_n()?;
        v0 = reference.no_load_speed_m_per_s()?;
    }
    let reference_time = started.elapsed().as_secs_f64() / REFERENCE_REPEATS as f64;
    let report_points = work_precision(setup, &scene, stall, v0, reference_time)?;
    files.extend(write_work_precision(&report_points, out_dir)?);
    let order = observed_order(&report_points, "return-mapping");
    let maps = vec![
        regularized_map(setup, &scene, v0)?,
        post_mass_map(setup, &scene, v0)?,
    ];
    for map in &maps {
        let stem = out_dir.join(format!("stability_{}", map.scheme));
        let chart = CategoryMap {
            title: format!("stability map: {} (single post, v = v₀/2)", map.scheme),
            x_label: "dt / T".into(),
            y_label: map.parameter.clone(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            xs: map.step_over_period.clone(),
            ys: map.values.clone(),
            cells: map.cells.clone(),
            categories: map.categories.clone(),
        };
        files.extend(write_category_map(&chart, &stem).map_err(chart_error(&stem))?);
    }
    let agreement = agreement(setup, &scene, out_dir, &mut files)?;
    let trends = trends(setup, out_dir, &mut files)?;
    // Fig. 6: one post at half the stall thrust.
    let operating = reference
        .at_load(0.5 * stall)?
        .map_or(0.5 * v0, |s| s.speed_m_per_s);
    let history = reference.post_history(operating, 3.0, 400)?;
    let stem = out_dir.join("fig6_post_history");
    files.extend(write_post_history_chart(
        "paper scene, 40 N, load ½ stall",
        &history,
        &stem,
    )?);
    let report = ValidationReport {
        reference_stall_thrust_n: stall,
        reference_no_load_speed_m_per_s: v0,
        reference_wall_time_s: reference_time,
        work_precision: report_points.clone(),
        return_mapping_order: order,
        mass_model_values: ["post-mass", "regularized-explicit"]
            .iter()
            .filter_map(|scheme| {
                work_precision_finest(&report_points, scheme).map(|p| {
                    (
                        scheme.to_string(),
                        p.stall_thrust_n,
                        p.no_load_speed_m_per_s,
                    )
                })
            })
            .collect(),
        stability_maps: maps,
        agreement,
        trends,
        files: files.clone(),
    };
    let path = out_dir.join("report.json");
    let json = serde_json::to_string_pretty(&report).map_err(|source| ValidationError::Json {
        what: "stick-slip report",
        source,
    })?;
    std::fs::write(&path, json).map_err(|source| ValidationError::Io {
        path: path.clone(),
        source,
    })?;
    let mut report = report;
    report.files.push(path);
    Ok(report)
}

fn relative(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn work_precision(
    setup: &ValidationSetup,
    scene: &DynamicScene,
    stall: f64,
    v0: f64,
    reference_time: f64,
) -> Result<Vec<WorkPrecisionPoint>> {
    let period = scene.wave.period_s();
    let mut points = vec![WorkPrecisionPoint {
        scheme: "event-driven".into(),
        steps_per_period: 0.0,
        wall_time_s: reference_time,
        stall_thrust_n: stall,
        no_load_speed_m_per_s: v0,
        stall_error: f64::EPSILON,
        no_load_error: f64::EPSILON,
    }];
    let top = setup.level.pick(7, 11, 14);
    let mut runs: Vec<(String, Integrator, f64)> = Vec::new();
    for k in 3..=top {
        let n = f64::from(1u32 << k);
        runs.push((
            "return-mapping".into(),
            Integrator::ReturnMapping { dt_s: period / n },
            n,
        ));
    }
    for k in 6..=top.max(7) {
        let n = f64::from(1u32 << k);
        runs.push((
            "post-mass".into(),
            Integrator::PostMass { dt_s: period / n },
            n,
        ));
    }
    let reg_top = setup.level.pick(12, 13, 15);
    for k in 12..=reg_top {
        let n = f64::from(1u32 << k);
        runs.push((
            "regularized-explicit".into(),
            Integrator::RegularizedExplicit {
                dt_s: period / n,
                regularization_speed_m_per_s: WORK_PRECISION_REGULARIZATION_M_PER_S,
            },
            n,
        ));
    }
    for (name, integrator, n) in runs {
        let mut s = scene.clone();
        s.integrator = integrator;
        s.options.stability = StabilityPolicy::Warn;
        let model = PeriodicAverageModel::new(&s)?;
        // Best of a few repetitions for short runs (the machine is shared; the minimum is the
        // least disturbed measurement).
        let mut best = f64::INFINITY;
        let mut outcome = None;
        for _ in 0..TIMING_REPEATS {
            let started = Instant::now();
            outcome = match (model.stall_thrust_n(), model.no_load_speed_m_per_s()) {
                (Ok(st), Ok(v)) => Some((st, v)),
                _ => None,
            };
            best = best.min(started.elapsed().as_secs_f64());
            if best > REPEAT_BELOW_S || outcome.is_none() {
                break;
            }
        }
        let Some((st, v)) = outcome else { continue };
        points.push(WorkPrecisionPoint {
            scheme: name,
            steps_per_period: n,
            wall_time_s: best,
            stall_thrust_n: st,
            no_load_speed_m_per_s: v,
            stall_error: relative(st, stall).max(f64::EPSILON),
            no_load_error: relative(v, v0).max(f64::EPSILON),
        });
    }
    Ok(points)
}

/// Observed order: least-squares slope of log(error) against log(steps per period) over all
/// points of a scheme (the error of a single step pair is erratic: the step grid aliases with
/// the touchdown phase).
fn observed_order(points: &[WorkPrecisionPoint], scheme: &str) -> (f64, f64) {
    let own: Vec<&WorkPrecisionPoint> = points.iter().filter(|p| p.scheme == scheme).collect();
    let slope = |pick: fn(&WorkPrecisionPoint) -> f64| {
        let xy: Vec<(f64, f64)> = own
            .iter()
            .map(|p| (p.steps_per_period.ln(), pick(p).ln()))
            .collect();
        let n = xy.len() as f64;
        if n < 2.0 {
            return f64::NAN;
        }
        let (mx, my) = (
            xy.iter().map(|p| p.0).sum::<f64>() / n,
            xy.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sxy: f64 = xy.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx: f64 = xy.iter().map(|p| (p.0 - mx).powi(2)).sum();
        -sxy / sxx
    };
    (slope(|p| p.stall_error), slope(|p| p.no_load_error))
}

/// Stall thrust (`no_load` false) or no-load speed of a point.
fn pick_value(p: &WorkPrecisionPoint, no_load: bool) -> f64 {
    if no_load {
        p.no_load_speed_m_per_s
    } else {
        p.stall_thrust_n
    }
}

fn work_precision_finest<'a>(
    points: &'a [WorkPrecisionPoint],
    scheme: &str,
) -> Option<&'a WorkPrecisionPoint> {
    points
        .iter()
        .filter(|p| p.scheme == scheme)
        .max_by(|a, b| a.steps_per_period.total_cmp(&b.steps_per_period))
}

fn write_work_precision(points: &[WorkPrecisionPoint], out_dir: &Path) -> Result<Vec<PathBuf>> {
    let schemes = [
        "event-driven",
        "return-mapping",
        "post-mass",
        "regularized-explicit",
    ];
    let panel = |title: &str, y_label: &str, no_load: bool| {
        let error = |p: &WorkPrecisionPoint| {
            if no_load {
                p.no_load_error
            } else {
                p.stall_error
            }
        };
        let mut chart = Chart::new(title, "wall time (s)", y_label).log_log();
        for scheme in schemes {
            let mut series: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.scheme == scheme)
                .map(|p| (p.wall_time_s, error(p)))
                .collect();
            series.sort_by(|a, b| a.0.total_cmp(&b.0));
            let label = match scheme {
                "event-driven" => "event-driven (closed form, error at round-off)".to_string(),
                "regularized-explicit" => format!(
                    "regularized-explicit (v_reg = {WORK_PRECISION_REGULARIZATION_M_PER_S} m/s)"
                ),
                other => other.to_string(),
            };
            chart
                .series
                .push(Series::new(label, series, Style::LineMarkers));
        }
        // Schemes with post mass converge to their own (massive-post) model: error against
        // their finest step, dashed.
        for scheme in ["post-mass", "regularized-explicit"] {
            let Some(finest) = work_precision_finest(points, scheme) else {
                continue;
            };
            let finest_value = pick_value(finest, no_load);
            let mut series: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.scheme == scheme && p.steps_per_period < finest.steps_per_period)
                .map(|p| {
                    (
                        p.wall_time_s,
                        relative(pick_value(p, no_load), finest_value).max(f64::EPSILON),
                    )
                })
                .collect();
            series.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.series.push(Series::new(
                format!("{scheme} vs its finest step"),
                series,
                Style::Dashed,
            ));
        }
        chart
    };
    let charts = [
        panel(
            "work-precision, paper scene at 40 N (solid: error vs massless closed form)",
            "relative error of stall thrust",
            false,
        ),
        panel("", "relative error of no-load speed", true),
    ];
    let stem = out_dir.join("work_precision");
    write_stacked(&charts, &stem).map_err(chart_error(&stem))
}

fn log_grid(lo_exp: f64, hi_exp: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 10f64.powf(lo_exp + (hi_exp - lo_exp) * i as f64 / (n - 1) as f64))
        .collect()
}

const MAP_CATEGORIES: [&str; 4] = [
    "accurate (within 2 % of the row's finest)",
    "stable, inaccurate",
    "oscillating at the step",
    "diverged",
];

/// Classify one row of probes against its finest stable result.
fn classify_row(probes: &[Option<StabilityProbe>]) -> Vec<usize> {
    let reference = probes
        .iter()
        .flatten()
        .find(|p| !p.diverged && !p.oscillating)
        .map(|p| p.mean_force);
    probes
        .iter()
        .map(|p| match p {
            None => 3,
            Some(p) if p.diverged || !p.mean_force.is_finite() => 3,
            Some(p) if p.oscillating => 2,
            Some(p) => match reference {
                Some(r) if (p.mean_force / r - 1.0).abs() <= MAP_ACCURACY => 0,
                _ => 1,
            },
        })
        .collect()
}

fn probe_row(
    scene: &DynamicScene,
    integrators: &[Integrator],
    speed: f64,
) -> Result<Vec<Option<StabilityProbe>>> {
    // Columns are passed from the finest step to the coarsest.
    integrators
        .iter()
        .map(|integrator| {
            let mut s = scene.clone();
            s.integrator = *integrator;
            s.options.stability = StabilityPolicy::Warn;
            let model = PeriodicAverageModel::new(&s)?;
            Ok(model.probe_at_speed(speed, MAP_PERIODS)?)
        })
        .collect()
}

fn regularized_map(
    setup: &ValidationSetup,
    scene: &DynamicScene,
    v0: f64,
) -> Result<StabilityMapReport> {
    let n = setup.level.pick(3, 7, 11);
    let steps = log_grid(-6.0, -2.0, n);
    let speeds = log_grid(-4.0, 0.0, n);
    let period = scene.wave.period_s();
    let setting = scene.stability_setting(ModelKind::PeriodicAverage);
    let mut cells = Vec::new();
    let mut limits = Vec::new();
    for &v_reg in &speeds {
        let integrators: Vec<Integrator> = steps
            .iter()
            .map(|&f| Integrator::RegularizedExplicit {
                dt_s: f * period,
                regularization_speed_m_per_s: v_reg,
            })
            .collect();
        let probes = probe_row(scene, &integrators, 0.5 * v0)?;
        cells.push(classify_row(&probes));
        let limit = integrators[0]
            .stability_limit(&setting)
            .map_or(f64::NAN, |l| l.limit_s / period);
        limits.push(limit);
    }
    Ok(StabilityMapReport {
        scheme: "regularized-explicit".into(),
        step_over_period: steps,
        values: speeds,
        parameter: "regularisation speed v_reg (m/s)".into(),
        cells,
        categories: MAP_CATEGORIES.iter().map(|c| c.to_string()).collect(),
        theoretical_limit_over_period: limits,
    })
}

fn post_mass_map(
    setup: &ValidationSetup,
    scene: &DynamicScene,
    v0: f64,
) -> Result<StabilityMapReport> {
    let n = setup.level.pick(3, 7, 11);
    let steps = log_grid(-4.0, -1.0, n);
    let masses = log_grid(-15.0, -10.0, n);
    let period = scene.wave.period_s();
    let mut cells = Vec::new();
    let mut limits = Vec::new();
    for &mass in &masses {
        let mut s = scene.clone();
        s.contact.post_mass_kg = Some(mass);
        let integrators: Vec<Integrator> = steps
            .iter()
            .map(|&f| Integrator::PostMass { dt_s: f * period })
            .collect();
        let probes = probe_row(&s, &integrators, 0.5 * v0)?;
        cells.push(classify_row(&probes));
        let setting = s.stability_setting(ModelKind::PeriodicAverage);
        limits.push(
            integrators[0]
                .stability_limit(&setting)
                .map_or(f64::NAN, |l| l.limit_s / period),
        );
    }
    Ok(StabilityMapReport {
        scheme: "post-mass".into(),
        step_over_period: steps,
        values: masses,
        parameter: "post mass m_p (kg)".into(),
        cells,
        categories: MAP_CATEGORIES.iter().map(|c| c.to_string()).collect(),
        theoretical_limit_over_period: limits,
    })
}

fn agreement(
    setup: &ValidationSetup,
    scene: &DynamicScene,
    out_dir: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<AgreementReport> {
    let periodic = PeriodicAverageModel::new(scene)?;
    let periodic_result = periodic.solve(&stick_slip::RunControl::none())?;
    let mut transient_scene = scene.clone();
    transient_scene.model = ModelChoice::Transient;
    transient_scene.integrator = Integrator::Auto;
    let (periods, average, loads) =
        setup
            .level
            .pick((60.0, 20.0, 2), (200.0, 80.0, 4), (400.0, 100.0, 6));
    transient_scene.options.transient.periods = periods;
    transient_scene.options.transient.average_periods = average;
    transient_scene.options.transient.curve_loads = loads;
    let transient = TransientModel::new(&transient_scene)?;
    let started = Instant::now();
    let (transient_result, _) = transient.solve_with_runs(&stick_slip::RunControl::none())?;
    let transient_time = started.elapsed().as_secs_f64();
    let stem = out_dir.join("speed_thrust_transient_vs_periodic");
    files.extend(write_speed_thrust_comparison(
        "paper scene 40 N: transient (100 phase groups) vs period average",
        &[
            ("period average", &periodic_result),
            ("transient", &transient_result),
        ],
        &stem,
    )?);
    let stall = periodic_result.stall_thrust_n;
    let loads = vec![0.0, 0.25 * stall, 0.5 * stall, 0.75 * stall];
    let (mut p_speeds, mut t_speeds) = (Vec::new(), Vec::new());
    for &load in &loads {
        p_speeds.push(periodic.at_load(load)?.map_or(0.0, |s| s.speed_m_per_s));
        t_speeds.push(
            transient
                .run(load, TransientStart::Estimate, false)?
                .speed_m_per_s,
        );
    }
    let max_speed_difference = p_speeds
        .iter()
        .zip(&t_speeds)
        .map(|(p, t)| relative(*t, *p))
        .fold(0.0, f64::max);
    // Step response from rest (slider history chart).
    let step = transient.run(0.0, TransientStart::Rest, true)?;
    if let Some(history) = &step.slider_history {
        let stem = out_dir.join("transient_step_response");
        files.extend(write_slider_history_chart(
            "step response from rest, paper scene 40 N, no load",
            history,
            &stem,
        )?);
    }
    // Incommensurate pitch.
    let mut odd = transient_scene.clone();
    odd.slider.layout = PostLayout::SquareArray {
        posts_per_side: 33,
        pitch_m: 121e-6,
    };
    odd.slider.preload_n = 10.0;
    let odd_periodic = PeriodicAverageModel::new(&DynamicScene {
        model: ModelChoice::PeriodicAverage,
        ..odd.clone()
    })?
    .no_load_speed_m_per_s()?;
    let odd_transient = TransientModel::new(&odd)?
        .run(0.0, TransientStart::Estimate, false)?
        .speed_m_per_s;
    // Burst of 20 periods with a bouncing slider.
    let mut burst = transient_scene.clone();
    burst.wave.burst_periods = Some(20.0);
    burst.slider.vertical = VerticalModel::Dynamic { damping_ratio: 0.2 };
    burst.options.transient.periods = 60.0;
    burst.options.transient.average_periods = 10.0;
    let burst_run = TransientModel::new(&burst)?.run(0.0, TransientStart::Rest, true)?;
    if let Some(history) = &burst_run.slider_history {
        let stem = out_dir.join("transient_burst");
        files.extend(write_slider_history_chart(
            "20-period burst, dynamic vertical (ζ = 0.2), paper scene 40 N",
            history,
            &stem,
        )?);
    }
    Ok(AgreementReport {
        loads_n: loads,
        periodic_speed_m_per_s: p_speeds,
        transient_speed_m_per_s: t_speeds,
        max_speed_difference,
        stall_thrust_n: (stall, transient_result.stall_thrust_n),
        no_load_speed_m_per_s: (
            periodic_result.no_load_speed_m_per_s,
            transient_result.no_load_speed_m_per_s,
        ),
        transient_wall_time_s: transient_time,
        incommensurate_no_load_m_per_s: (odd_periodic, odd_transient),
        burst_displacement_m: burst_run.displacement_m,
        burst_peak_speed_m_per_s: burst_run.peak_speed_m_per_s,
    })
}

fn trends(
    setup: &ValidationSetup,
    out_dir: &Path,
    files: &mut Vec<PathBuf>,
) -> Result<Vec<TrendCurve>> {
    let count = setup.level.pick(3, 20, 20);
    let preloads: Vec<f64> = (1..=count)
        .map(|i| 100.0 * i as f64 / count as f64)
        .collect();
    let sweep = |label: String, k_n: f64, k_t: f64, side: usize| -> Result<TrendCurve> {
        let mut curve = TrendCurve {
            label,
            preload_n: preloads.clone(),
            stall_thrust_n: vec![],
            no_load_speed_m_per_s: vec![],
        };
        for &p in &preloads {
            let mut scene = DynamicScene::paper_default(k_n, k_t);
            scene.slider.layout = PostLayout::SquareArray {
                posts_per_side: side,
                pitch_m: 4e-3 / side as f64,
            };
            scene.slider.preload_n = p;
            let model = PeriodicAverageModel::new(&DynamicScene {
                model: ModelChoice::PeriodicAverage,
                ..scene
            })?;
            curve.stall_thrust_n.push(model.stall_thrust_n()?.max(0.0));
            curve
                .no_load_speed_m_per_s
                .push(model.no_load_speed_m_per_s()?);
        }
        Ok(curve)
    };
    let mut curves = Vec::new();
    for side in [100, 80, 66, 50, 33] {
        curves.push(sweep(
            format!("{} posts, 20 µm", side * side),
            setup.k_n_n_per_m,
            setup.k_t_n_per_m,
            side,
        )?);
    }
    curves.push(sweep(
        "1600 posts, 50 µm".into(),
        setup.k_n_50um_n_per_m,
        setup.k_t_50um_n_per_m,
        40,
    )?);
    let panel =
        |title: &str, y: &str, selected: &[&TrendCurve], pick: fn(&TrendCurve) -> &Vec<f64>| {
            let mut chart = Chart::new(title, "preload (N)", y);
            for c in selected {
                let points = c
                    .preload_n
                    .iter()
                    .copied()
                    .zip(pick(c).iter().copied())
                    .collect();
                chart
                    .series
                    .push(Series::new(c.label.clone(), points, Style::LineMarkers));
            }
            chart
        };
    let counts: Vec<&TrendCurve> = curves[..5].iter().collect();
    let stem = out_dir.join("trend_post_count");
    files.extend(
        write_stacked(
            &[
                panel(
                    "post count (η = 0.36; paper Figs 7–8)",
                    "stall thrust (N)",
                    &counts,
                    |c| &c.stall_thrust_n,
                ),
                panel("", "no-load speed (m/s)", &counts, |c| {
                    &c.no_load_speed_m_per_s
                }),
            ],
            &stem,
        )
        .map_err(chart_error(&stem))?,
    );
    let diameters: Vec<&TrendCurve> = vec![&curves[0], &curves[5]];
    let stem = out_dir.join("trend_diameter");
    files.extend(
        write_stacked(
            &[
                panel(
                    "20 µm vs 50 µm at equal contact area (paper Figs 9–12)",
                    "stall thrust (N)",
                    &diameters,
                    |c| &c.stall_thrust_n,
                ),
                panel("", "no-load speed (m/s)", &diameters, |c| {
                    &c.no_load_speed_m_per_s
                }),
            ],
            &stem,
        )
        .map_err(chart_error(&stem))?,
    );
    // Paper-scene speed–thrust curves at three preloads.
    let mut results = Vec::new();
    for p in [10.0, 40.0, 100.0] {
        let mut scene = DynamicScene::paper_default(setup.k_n_n_per_m, setup.k_t_n_per_m);
        scene.slider.preload_n = p;
        results.push((
            format!("P = {p} N"),
            PeriodicAverageModel::new(&scene)?.solve(&stick_slip::RunControl::none())?,
        ));
    }
    let labelled: Vec<(&str, &DynamicResult)> =
        results.iter().map(|(l, r)| (l.as_str(), r)).collect();
    let stem = out_dir.join("speed_thrust_preloads");
    files.extend(write_speed_thrust_comparison(
        "paper scene (10000 posts of 20 µm, η = 0.36)",
        &labelled,
        &stem,
    )?);
    Ok(curves)
}
