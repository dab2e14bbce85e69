//! Monte Carlo propagation of a scene's scatter (`sawdrive uq`): N samples of the `[scatter]`
//! inputs ([`crate::scatter`]), each evaluated by the [`Evaluator`] (in the `sawdrive`
//! library: a whole-slider contact solve and a dynamic curve, no FEM), in parallel (rayon); bands (mean, P5/P50/P95 with
//! 95 % order-statistic intervals), histograms, rank-correlation sensitivity.
//!
//! Resume: each finished sample is written atomically to
//! `OUT/.uq-samples/<inputs hash>/sample-<k>.json` (the hash covers the resolved scene, the
//! scatter, the seed and the model versions; sample k does not depend on N), and a rerun reuses
//! every sample found there, so an interrupted run loses only the samples in flight. The results
//! folder `OUT/<scene>-uq/` is replaced only when the run completes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use atomic_files::StagedDir;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::error::StudyError;
use crate::evaluator::{
    CoupledCost, EvaluationCost, Evaluator, Fidelity, MotorOutputs, MotorSample, OUTPUT_NAMES,
    SceneFacts,
};
use crate::files::{staged_results, write_atomically};
use crate::scatter::ScatterSpec;
use crate::{Band, ScatterInput, Sensitivity, band, draw_inputs, histogram, rank_inputs};

/// Speeds of the band chart's grid.
const BAND_SPEEDS: usize = 41;
/// Bins of each histogram.
const HISTOGRAM_BINS: usize = 20;
/// Version of the sample files' layout (part of the inputs hash).
const SAMPLE_FORMAT: u32 = 4;

/// How to run a UQ.
#[derive(Debug, Clone)]
pub struct UqOptions {
    /// Samples (≥ 1).
    pub samples: usize,
    /// Seed.
    pub seed: u64,
    /// Results go to `out_dir/<scene>-uq/`, samples to `out_dir/.uq-samples/`.
    pub out_dir: PathBuf,
    /// Static model of each sample.
    pub fidelity: Fidelity,
    /// Write charts and CSV besides `summary.json`.
    pub write_files: bool,
}

/// One finished sample (also its resume file).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SampleRecord {
    /// Index k.
    pub index: u64,
    /// Drawn inputs, in the order of `UqReport::input_names`.
    pub inputs: Vec<f64>,
    /// Seed of its post heights.
    pub scatter_seed: u64,
    /// Outputs in the order of [`OUTPUT_NAMES`].
    pub outputs: Vec<f64>,
    /// Its speed–thrust curve, (speed m/s, thrust N).
    pub curve: Vec<(f64, f64)>,
    /// The dynamic model that ran (`lumped` or `coupled`).
    #[serde(default)]
    pub dynamics_model: String,
    /// Wall time (s).
    pub wall_time_s: f64,
    /// Where its time went.
    pub cost: EvaluationCost,
}

/// Where the samples' time went (means over the samples computed in this run, each measured on
/// its own thread, so they add up to CPU time, not wall time).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Default)]
pub struct UqCost {
    /// Building the nominal scene's lattice operator, once (s).
    pub operator_s: f64,
    /// Samples computed in this run (not resumed).
    pub computed_samples: usize,
    /// Mean static part of a sample: post offsets, contact solves of every phase, η fit (s).
    pub static_s: f64,
    /// Mean part of `static_s` spent building a sample's own operator (another post diameter;
    /// 0 for samples sharing the nominal one) (s).
    pub sample_operator_s: f64,
    /// Mean dynamic part of a sample: springs and the speed–thrust curve (s).
    pub dynamic_s: f64,
    /// Samples that built their own operator (another post diameter).
    pub operators_built: usize,
    /// Computed samples that ran the coupled model.
    pub coupled_samples: usize,
    /// Mean coupled part of `dynamic_s` over the samples that ran it, by piece (s).
    pub coupled: CoupledCost,
}

/// P5/P50/P95 of thrust on a speed grid.
#[derive(Debug, Clone, Serialize)]
pub struct CurveBand {
    /// Speeds (m/s).
    pub speed_m_per_s: Vec<f64>,
    /// P5 of thrust (N).
    pub thrust_p5_n: Vec<f64>,
    /// Median thrust (N).
    pub thrust_p50_n: Vec<f64>,
    /// P95 of thrust (N).
    pub thrust_p95_n: Vec<f64>,
}

/// The result of `sawdrive uq` (its JSON keys are the command's contract).
#[derive(Debug, Clone, Serialize)]
pub struct UqReport {
    /// Scene name.
    pub scene: String,
    /// Samples.
    pub samples: usize,
    /// Seed.
    pub seed: u64,
    /// Static model of every sample.
    pub fidelity: &'static str,
    /// The dynamic model of the samples and how it was chosen (`model.dynamics`).
    pub dynamics: String,
    /// Samples (of `samples`, resumed ones included) that ran the coupled model; the others
    /// ran the lumped one.
    pub coupled_samples: usize,
    /// The scatter.
    pub scatter: ScatterSpec,
    /// Names (with units) of the scattered inputs.
    pub input_names: Vec<String>,
    /// Bands.
    pub effective_contact_ratio: Band,
    /// Bands.
    pub stall_thrust_n: Band,
    /// Bands.
    pub no_load_speed_m_per_s: Band,
    /// Bands.
    pub max_output_power_w: Band,
    /// Bands.
    pub efficiency: Band,
    /// The deterministic run (nominal inputs, ideal posts), same model.
    pub deterministic: Vec<(String, f64)>,
    /// Per output, the inputs ranked by |Spearman ρ|.
    pub sensitivity: Vec<(String, Vec<Sensitivity>)>,
    /// Thrust band along speed.
    pub curve_band: CurveBand,
    /// Samples reused from an earlier, interrupted run.
    pub resumed_samples: usize,
    /// Samples whose model failed (index, error): not in the bands.
    pub failed_samples: Vec<(u64, String)>,
    /// Mean wall time of one computed sample (s), as measured per sample (threads overlap).
    pub sample_cost_s: f64,
    /// The samples' cost by part.
    pub cost: UqCost,
    /// Wall time of the whole run (s).
    pub wall_time_s: f64,
    /// Files written, relative to the results folder.
    pub files: Vec<String>,
}

/// Hash of everything a sample depends on.
fn inputs_hash<E: Evaluator>(
    ev: &E,
    scene: &E::Scene,
    scatter: &ScatterSpec,
    seed: u64,
    fidelity: Fidelity,
) -> Result<String, StudyError> {
    let mut h = Sha256::new();
    h.update(ev.scene_bytes(scene).map_err(StudyError::Model)?);
    h.update(serde_json::to_vec(scatter)?);
    h.update(serde_json::to_vec(&fidelity)?);
    h.update(seed.to_le_bytes());
    h.update(ev.model_versions());
    h.update(SAMPLE_FORMAT.to_le_bytes());
    Ok(h.finalize()
        .iter()
        .take(12)
        .map(|b| format!("{b:02x}"))
        .collect())
}

fn record(
    index: u64,
    inputs: Vec<f64>,
    sample: &MotorSample,
    out: &MotorOutputs,
    wall: f64,
) -> SampleRecord {
    SampleRecord {
        index,
        inputs,
        scatter_seed: sample.scatter_seed,
        outputs: out.values().to_vec(),
        curve: out
            .curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect(),
        dynamics_model: out.dynamics_model.to_owned(),
        wall_time_s: wall,
        cost: out.cost,
    }
}

/// A saved sample, if present and readable (a damaged file is recomputed).
fn load_sample(path: &Path) -> Option<SampleRecord> {
    let bytes = std::fs::read(path).ok()?;
    serde_json::from_slice(&bytes).ok()
}

/// Thrust of a curve at speed v (linear interpolation; 0 beyond its fastest point).
fn thrust_at(curve: &[(f64, f64)], v: f64) -> f64 {
    let mut pts = curve.to_vec();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    match pts.windows(2).find(|w| w[0].0 <= v && v <= w[1].0) {
        Some(w) if w[1].0 > w[0].0 => w[0].1 + (v - w[0].0) / (w[1].0 - w[0].0) * (w[1].1 - w[0].1),
        Some(w) => w[0].1,
        None if pts.first().is_some_and(|p| v < p.0) => pts[0].1,
        None => 0.0,
    }
}

fn curve_band(records: &[SampleRecord]) -> Result<CurveBand, StudyError> {
    let vmax = records
        .iter()
        .flat_map(|r| r.curve.iter().map(|p| p.0))
        .fold(0.0, f64::max);
    let speeds: Vec<f64> = (0..BAND_SPEEDS)
        .map(|k| vmax * k as f64 / (BAND_SPEEDS - 1) as f64)
        .collect();
    let mut band_out = CurveBand {
        speed_m_per_s: speeds.clone(),
        thrust_p5_n: Vec::new(),
        thrust_p50_n: Vec::new(),
        thrust_p95_n: Vec::new(),
    };
    for v in speeds {
        let t: Vec<f64> = records.iter().map(|r| thrust_at(&r.curve, v)).collect();
        let b = band(&t, "thrust_n")?;
        band_out.thrust_p5_n.push(b.p5);
        band_out.thrust_p50_n.push(b.p50);
        band_out.thrust_p95_n.push(b.p95);
    }
    Ok(band_out)
}

/// Most Monte Carlo samples of one study (`uq --samples`, a design's `samples`): about 150 bytes
/// of results each, and seconds of work each, so 10^5 samples are days of CPU time already.
pub const MAX_SAMPLES: usize = 100_000;

/// `--samples` within 1 to [`MAX_SAMPLES`], else the error that says so.
pub fn check_samples(samples: usize) -> Result<(), StudyError> {
    if (1..=MAX_SAMPLES).contains(&samples) {
        return Ok(());
    }
    Err(StudyError::input(
        "--samples",
        format!(
            "{samples} is outside 1 to {MAX_SAMPLES} (each sample is a static and a dynamic solve; the band's quantiles converge long before)"
        ),
    ))
}

/// Runs the UQ of `scene` under `scatter`; writes `OUT/<scene>-uq/` when complete.
pub fn run_uq<E: Evaluator>(
    ev: &E,
    scene: &E::Scene,
    scatter: &ScatterSpec,
    options: &UqOptions,
) -> Result<(UqReport, PathBuf), StudyError> {
    let (report, staged) = run_uq_staged(ev, scene, scatter, options)?;
    Ok((report, staged.commit()?))
}

/// One Monte Carlo sample of a UQ run: drawn, evaluated and saved (`resumed` from its saved
/// file when one is there).
struct SampleRun<'a, E: Evaluator> {
    ev: &'a E,
    model: &'a E::Prepared,
    scene: &'a E::Scene,
    scatter: &'a ScatterSpec,
    inputs: &'a [ScatterInput],
    seed: u64,
    /// Folder of the saved samples.
    cache: &'a Path,
}

impl<E: Evaluator> SampleRun<'_, E> {
    /// Sample `k` and whether it was resumed.
    fn run(&self, k: u64) -> Result<(SampleRecord, bool), StudyError> {
        let path = self.cache.join(format!("sample-{k}.json"));
        if let Some(r) = load_sample(&path).filter(|r| r.index == k) {
            return Ok((r, true));
        }
        let t = Instant::now();
        let (values, field_seed) = draw_inputs(self.inputs, self.seed, k);
        let sample = self.scatter.sample(&values, field_seed);
        // The values used (μ_k clamped to ≤ μ_s), for the CSV and the ranking.
        let values = vec![
            sample.preload_n,
            sample.post_diameter_m,
            sample.mu_static,
            sample.mu_kinetic,
            sample.tilt_x_m,
            sample.tilt_y_m,
            sample.bow_m,
        ];
        let out = self
            .ev
            .evaluate(self.model, self.scene, &sample)
            .map_err(|source| {
                // The sample's inputs, so that the failure can be reproduced with `run --set`.
                let drawn: Vec<String> = self
                    .inputs
                    .iter()
                    .zip(&values)
                    .map(|(i, v)| format!("{} = {v:e}", i.name))
                    .collect();
                StudyError::Sample {
                    index: k,
                    seed: self.seed,
                    field_seed,
                    drawn: drawn.join(", "),
                    source,
                }
            })?;
        let r = record(k, values, &sample, &out, t.elapsed().as_secs_f64());
        write_atomically(&path, serde_json::to_vec(&r)?)?;
        Ok((r, false))
    }
}

/// The samples that ran (each with whether it was resumed) and the failed ones by index: a
/// sample whose model fails (e.g. a stick/slip event loop that does not converge) is reported
/// and left out of the bands; the run fails only if every sample does.
type SampleOutcomes = (Vec<(SampleRecord, bool)>, Vec<(u64, String)>);

fn gather(
    outcomes: Vec<Result<(SampleRecord, bool), StudyError>>,
) -> Result<SampleOutcomes, StudyError> {
    let mut results = Vec::new();
    let mut failed_samples = Vec::new();
    for (k, o) in outcomes.into_iter().enumerate() {
        match o {
            Ok(r) => results.push(r),
            Err(e) => failed_samples.push((k as u64, e.to_string())),
        }
    }
    if results.is_empty() {
        return Err(StudyError::Study {
            stage: "uq",
            message: format!("every sample failed; first: {}", failed_samples[0].1),
        });
    }
    Ok((results, failed_samples))
}

/// The cost of the samples computed in this run (`fresh`), with the nominal operator's.
fn uq_cost(fresh: &[&SampleRecord], operator_s: f64) -> UqCost {
    let mean = |f: &dyn Fn(&SampleRecord) -> f64| {
        fresh.iter().map(|r| f(r)).sum::<f64>() / fresh.len().max(1) as f64
    };
    let coupled: Vec<&CoupledCost> = fresh
        .iter()
        .filter(|r| r.dynamics_model == "coupled")
        .map(|r| &r.cost.coupled)
        .collect();
    let mean_coupled = |f: &dyn Fn(&CoupledCost) -> f64| {
        coupled.iter().map(|c| f(c)).sum::<f64>() / coupled.len().max(1) as f64
    };
    UqCost {
        operator_s,
        computed_samples: fresh.len(),
        static_s: mean(&|r| r.cost.static_s),
        sample_operator_s: mean(&|r| r.cost.operator_s),
        dynamic_s: mean(&|r| r.cost.dynamic_s),
        operators_built: fresh.iter().filter(|r| r.cost.operator_built).count(),
        coupled_samples: coupled.len(),
        coupled: CoupledCost {
            normal_grid_s: mean_coupled(&|c| c.normal_grid_s),
            stall_s: mean_coupled(&|c| c.stall_s),
            no_load_s: mean_coupled(&|c| c.no_load_s),
            points_s: mean_coupled(&|c| c.points_s),
            periods: (mean_coupled(&|c| c.periods as f64)).round() as usize,
        },
    }
}

/// Each output's band over `records` and its inputs ranked by |Spearman ρ|.
type BandsAndRanks = (Vec<Band>, Vec<(String, Vec<Sensitivity>)>);

fn bands_and_ranks(
    records: &[SampleRecord],
    inputs: &[ScatterInput],
) -> Result<BandsAndRanks, StudyError> {
    let column = |k: usize| records.iter().map(|r| r.outputs[k]).collect::<Vec<f64>>();
    let bands: Vec<Band> = (0..OUTPUT_NAMES.len())
        .map(|k| band(&column(k), OUTPUT_NAMES[k]).map_err(StudyError::from))
        .collect::<Result<_, _>>()?;
    let input_columns: Vec<(String, Vec<f64>)> = inputs
        .iter()
        .enumerate()
        .map(|(i, inp)| {
            (
                inp.name.clone(),
                records.iter().map(|r| r.inputs[i]).collect(),
            )
        })
        .collect();
    let sensitivity = (0..OUTPUT_NAMES.len())
        .map(|k| {
            (
                OUTPUT_NAMES[k].to_owned(),
                rank_inputs(&input_columns, &column(k)),
            )
        })
        .collect();
    Ok((bands, sensitivity))
}

/// The checked inputs of a UQ run: the scene's facts, the scattered inputs, the staged
/// results folder and the folder of the saved samples.
fn prepare_uq<E: Evaluator>(
    ev: &E,
    scene: &E::Scene,
    scatter: &ScatterSpec,
    options: &UqOptions,
) -> Result<(SceneFacts, Vec<ScatterInput>, StagedDir, PathBuf), StudyError> {
    check_samples(options.samples).map_err(|e| StudyError::Study {
        stage: "uq",
        message: e.to_string(),
    })?;
    ev.check_study(scene).map_err(StudyError::Model)?;
    let facts = ev.facts(scene);
    let inputs = scatter.inputs(&facts).map_err(|e| StudyError::Study {
        stage: "uq",
        message: e.to_string(),
    })?;
    let destination = options.out_dir.join(format!("{}-uq", facts.name));
    let staged = staged_results(&destination, "uq")?;
    let cache = options.out_dir.join(".uq-samples").join(inputs_hash(
        ev,
        scene,
        scatter,
        options.seed,
        options.fidelity,
    )?);
    Ok((facts, inputs, staged, cache))
}

/// [`run_uq`] up to the commit: the report and its complete results folder, still staged. A
/// caller that may be interrupted (the Python package) commits it itself, so that an
/// interrupted call commits nothing; dropped, the staged folder is removed. The samples are
/// saved for resume either way.
pub fn run_uq_staged<E: Evaluator>(
    ev: &E,
    scene: &E::Scene,
    scatter: &ScatterSpec,
    options: &UqOptions,
) -> Result<(UqReport, StagedDir), StudyError> {
    let start = Instant::now();
    let (facts, inputs, staged, cache) = prepare_uq(ev, scene, scatter, options)?;
    // The operator is built once here; every sample with the nominal post diameter reuses it.
    let built = Instant::now();
    let model = ev
        .prepare(scene, options.fidelity)
        .map_err(StudyError::Model)?;
    let operator_s = built.elapsed().as_secs_f64();
    let nominal = ev
        .evaluate(&model, scene, &MotorSample::nominal(&facts))
        .map_err(StudyError::Model)?;
    let runner = SampleRun {
        ev,
        model: &model,
        scene,
        scatter,
        inputs: &inputs,
        seed: options.seed,
        cache: &cache,
    };
    let outcomes: Vec<_> = (0..options.samples as u64)
        .into_par_iter()
        .map(|k| runner.run(k))
        .collect();
    let (results, failed_samples) = gather(outcomes)?;
    let resumed_samples = results.iter().filter(|r| r.1).count();
    let fresh: Vec<&SampleRecord> = results.iter().filter(|r| !r.1).map(|r| &r.0).collect();
    let computed: Vec<f64> = fresh.iter().map(|r| r.wall_time_s).collect();
    let cost = uq_cost(&fresh, operator_s);
    let records: Vec<SampleRecord> = results.into_iter().map(|r| r.0).collect();
    let (bands, sensitivity) = bands_and_ranks(&records, &inputs)?;
    let mut report = UqReport {
        scene: facts.name.clone(),
        samples: records.len(),
        seed: options.seed,
        fidelity: ev.fidelity(&model).label(),
        dynamics: ev.dynamics_policy(scene),
        coupled_samples: records
            .iter()
            .filter(|r| r.dynamics_model == "coupled")
            .count(),
        scatter: scatter.clone(),
        input_names: inputs.iter().map(|i| i.name.clone()).collect(),
        effective_contact_ratio: bands[0],
        stall_thrust_n: bands[1],
        no_load_speed_m_per_s: bands[2],
        max_output_power_w: bands[3],
        efficiency: bands[4],
        deterministic: OUTPUT_NAMES
            .iter()
            .map(|s| s.to_string())
            .zip(nominal.values())
            .collect(),
        sensitivity,
        curve_band: curve_band(&records)?,
        resumed_samples,
        failed_samples,
        sample_cost_s: if computed.is_empty() {
            0.0
        } else {
            computed.iter().sum::<f64>() / computed.len() as f64
        },
        cost,
        wall_time_s: 0.0,
        files: Vec::new(),
    };
    if options.write_files {
        report.files = write_uq_files(&report, &records, &nominal, staged.path())?;
    }
    report.files.push("summary.json".into());
    report.wall_time_s = start.elapsed().as_secs_f64();
    staged.write("summary.json", serde_json::to_vec_pretty(&report)?)?;
    Ok((report, staged))
}

fn samples_csv(report: &UqReport, records: &[SampleRecord]) -> String {
    let mut s = format!(
        "sample,scatter_seed,{},{}\n",
        report.input_names.join(","),
        OUTPUT_NAMES.join(",")
    );
    for r in records {
        let cells: Vec<String> = r
            .inputs
            .iter()
            .chain(&r.outputs)
            .map(|v| format!("{v:e}"))
            .collect();
        s.push_str(&format!(
            "{},{},{}\n",
            r.index,
            r.scatter_seed,
            cells.join(",")
        ));
    }
    s
}

/// `samples.csv`, the speed–thrust band chart and the histograms.
fn write_uq_files(
    report: &UqReport,
    records: &[SampleRecord],
    nominal: &MotorOutputs,
    dir: &Path,
) -> Result<Vec<String>, StudyError> {
    use charts::{Chart, Series, Style, write_chart, write_stacked};
    let mut files = vec!["samples.csv".to_owned()];
    write_atomically(&dir.join("samples.csv"), samples_csv(report, records))?;
    let b = &report.curve_band;
    let pts = |t: &[f64]| {
        b.speed_m_per_s
            .iter()
            .copied()
            .zip(t.iter().copied())
            .collect::<Vec<_>>()
    };
    let mut chart = Chart::new(
        format!(
            "{}: speed–thrust band, {} samples",
            report.scene, report.samples
        ),
        "speed (m/s)",
        "thrust (N)",
    );
    chart
        .series
        .push(Series::new("P5", pts(&b.thrust_p5_n), Style::Dashed));
    chart
        .series
        .push(Series::new("P50", pts(&b.thrust_p50_n), Style::Line));
    chart
        .series
        .push(Series::new("P95", pts(&b.thrust_p95_n), Style::Dashed));
    chart.series.push(Series::new(
        "deterministic",
        nominal
            .curve
            .iter()
            .map(|p| (p.speed_m_per_s, p.thrust_n))
            .collect(),
        Style::Markers,
    ));
    for f in write_chart(&chart, &dir.join("band"))? {
        files.push(
            f.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned(),
        );
    }
    let mut hists = Vec::new();
    for (k, name) in OUTPUT_NAMES.iter().enumerate() {
        let values: Vec<f64> = records.iter().map(|r| r.outputs[k]).collect();
        let h = histogram(&values, HISTOGRAM_BINS, name)?;
        let mut steps = Vec::new();
        for (i, c) in h.counts.iter().enumerate() {
            let (lo, hi) = (h.edges[i], h.edges[i + 1]);
            steps.extend([(lo, 0.0), (lo, *c as f64), (hi, *c as f64), (hi, 0.0)]);
        }
        let mut c = Chart::new(format!("histogram of {name}"), name.to_string(), "samples");
        c.series.push(Series::new(*name, steps, Style::Line));
        hists.push(c);
    }
    for f in write_stacked(&hists, &dir.join("histograms"))? {
        files.push(
            f.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned(),
        );
    }
    Ok(files)
}
