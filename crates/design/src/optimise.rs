//! Bounded, constrained optimisation of an expensive black-box model, and its multi-fidelity use.
//!
//! Method (why): the design spaces here are small boxes (2–5 variables: post diameter, posts per
//! side, height, preload) whose objective comes from a contact solve and a period-average
//! dynamic curve — no gradients, mild noise from solver tolerances, integer variables (post
//! counts) and constraints that cut the box. So:
//! 1. a Latin-hypercube pre-search of the unit box (McKay, Beckman & Conover 1979; seeded) maps
//!    the landscape and finds feasible regions with one parallel batch of evaluations;
//! 2. Nelder–Mead (Nelder & Mead 1965; α = 1, γ = 2, ρ = σ = ½) from the best few pre-search
//!    points refines each, in the unit box with coordinates clamped to it, integer variables
//!    rounded. It only *compares* points, so constraints are handled exactly by feasibility
//!    first (Deb 2000): any feasible point beats any infeasible one, infeasible ones are ordered
//!    by their total relative violation, feasible ones by the objective.
//!    It is written here (≈ 60 lines) rather than taken from argmin. argmin 0.10.0 was checked
//!    (it is in the workspace's allowed set): its `NelderMead` (a) minimises a scalar cost, so
//!    feasibility-first would become a penalty, which reshapes the objective exactly at the
//!    active constraint where the motor's optima sit (`min_gap`, validation/design/README.md);
//!    (b) stops on the standard deviation of the simplex's costs (`with_sd_tolerance`), not on
//!    the simplex's size in x: our stated tolerance is a fraction of each range, and the costs
//!    of a simplex on a plateau (whole post counts make plateaus) have zero spread long before
//!    the simplex is small; (c) knows no box: a transform (clamp or logistic map inside the
//!    cost) would be needed, and a clamp makes flat regions outside the box that trigger (b);
//!    (d) sorts the simplex with `partial_cmp(..).unwrap_or(Equal)`, so a failed evaluation
//!    (NaN) would stay in the simplex silently, where here it is an infeasible point named in
//!    the evaluations. Its `ParticleSwarm` has bounds, but needs particles × iterations
//!    (≥ 200) evaluations of a 0.1–1 s model and draws from its own RNG, not the workspace's
//!    seeded SplitMix64. The rule here is the textbook one (coefficients above), checked on
//!    toy optima with known answers (tests below).
//!
//! Tolerance: Nelder–Mead stops when every vertex is within [`OptimiserSettings::x_tolerance`]
//! (a fraction of each variable's range) of the best one, or at its evaluation budget; on a
//! smooth unimodal objective the optimum is then found within that fraction of the range.
//!
//! Multi-fidelity ([`multi_fidelity`]): the search runs on a cheap model; the best distinct
//! feasible designs (finalists) are re-evaluated by the full model, and a compass search on the
//! full model, started at the best finalist, refines it (the cheap
//! model can be biased: for the motor, the 8-row patch overestimates η by ≈ 30 % at the optimum,
//! validation/design/README.md). The optimum is the best full-model evaluation. Every
//! [`Evaluation`] carries its fidelity.

use std::collections::BTreeMap;
use std::collections::HashMap;

use motor::rng::SplitMix64;
use rayon::prelude::*;
use serde::Serialize;

use crate::error::{DesignError, Result, invalid};

/// Nelder–Mead coefficients: reflection, expansion, contraction, shrink.
const NM_REFLECT: f64 = 1.0;
const NM_EXPAND: f64 = 2.0;
const NM_CONTRACT: f64 = 0.5;
const NM_SHRINK: f64 = 0.5;
/// Initial simplex edge of the search, as a fraction of each variable's range.
const NM_INITIAL_STEP: f64 = 0.1;
/// Initial step of the full-fidelity refinement's compass search, as a fraction of each
/// variable's range: half the search's simplex edge, since it starts at a confirmed finalist.
const REFINE_INITIAL_STEP: f64 = 0.05;

/// A design variable; `name` carries the unit (`post_diameter_m`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variable {
    /// Name with unit.
    pub name: String,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound (≥ lower).
    pub upper: f64,
    /// Rounded to whole numbers (e.g. posts per side).
    pub integer: bool,
}

impl Variable {
    /// Checks the bounds; errors name `variables.<name>`.
    pub fn validate(&self) -> Result<()> {
        let key = format!("variables.{}", self.name);
        if !(self.lower.is_finite() && self.upper.is_finite()) {
            return Err(invalid(key, "bounds must be finite"));
        }
        if self.lower > self.upper {
            return Err(invalid(
                key,
                format!(
                    "bounds reversed: lower {} > upper {}",
                    self.lower, self.upper
                ),
            ));
        }
        if self.integer && self.lower.ceil() > self.upper.floor() {
            return Err(invalid(key, "no whole number between the bounds"));
        }
        Ok(())
    }

    /// The value at unit coordinate u ∈ [0, 1] (rounded for integers, inside the bounds).
    pub fn at(&self, u: f64) -> f64 {
        let x = self.lower + u.clamp(0.0, 1.0) * (self.upper - self.lower);
        if self.integer {
            x.round().clamp(self.lower.ceil(), self.upper.floor())
        } else {
            x
        }
    }
}

/// Whether the objective is maximised or minimised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sense {
    /// Larger is better.
    Maximise,
    /// Smaller is better.
    Minimise,
}

/// The objective: an output's name and its sense.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Objective {
    /// Output name (with unit).
    pub output: String,
    /// Sense.
    pub sense: Sense,
}

/// A model's answer at one design.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Outcome {
    /// Objective value (in the objective's unit).
    pub objective: f64,
    /// Violated constraints by name, with the relative violation (> 0); empty: feasible.
    pub violations: Vec<(String, f64)>,
    /// Further outputs to report (name with unit → value).
    pub outputs: BTreeMap<String, f64>,
}

impl Outcome {
    /// Whether every constraint holds.
    pub fn feasible(&self) -> bool {
        self.violations.is_empty() && self.objective.is_finite()
    }

    fn total_violation(&self) -> f64 {
        self.violations.iter().map(|v| v.1).sum()
    }
}

/// Which model computed a number.
pub type Fidelity = String;

/// One evaluated design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// Variable values, in the variables' order.
    pub x: Vec<f64>,
    /// The model that computed it.
    pub fidelity: Fidelity,
    /// `presearch`, `nelder_mead`, `confirm`, `refine` or `sensitivity`.
    pub stage: &'static str,
    /// Its result.
    pub outcome: Outcome,
}

/// Search settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OptimiserSettings {
    /// Latin-hypercube points of the pre-search (≥ 1).
    pub presearch_points: usize,
    /// Nelder–Mead runs, from the best distinct pre-search points.
    pub starts: usize,
    /// Evaluation budget of each Nelder–Mead run.
    pub max_evaluations_per_start: usize,
    /// Convergence: simplex size as a fraction of each variable's range.
    pub x_tolerance: f64,
    /// Seed of the Latin hypercube.
    pub seed: u64,
    /// Designs confirmed at full fidelity ([`multi_fidelity`]).
    pub finalists: usize,
    /// Evaluation budget of the full-fidelity compass-search refinement from the best confirmed
    /// finalist ([`multi_fidelity`]); 0: no refinement.
    pub refine_evaluations: usize,
}

impl Default for OptimiserSettings {
    /// 32 pre-search points, 3 starts of ≤ 60 evaluations, tolerance 1 % of the range, 3 finalists,
    /// a refinement of ≤ 20 full-fidelity evaluations.
    fn default() -> Self {
        Self {
            presearch_points: 32,
            starts: 3,
            max_evaluations_per_start: 60,
            x_tolerance: 0.01,
            seed: 1,
            finalists: 3,
            refine_evaluations: 20,
        }
    }
}

/// Most evaluations any one count of the search may ask for (pre-search points, starts ×
/// evaluations per start, finalists, refinement): each evaluation is a pipeline run of
/// milliseconds to seconds, so 10^5 is already days of work.
pub const MAX_EVALUATIONS: usize = 100_000;

impl OptimiserSettings {
    /// Checks the settings; errors name `optimiser.<field>`.
    pub fn validate(&self) -> Result<()> {
        if self.presearch_points == 0 {
            return Err(invalid("optimiser.presearch_points", "must be ≥ 1"));
        }
        let starts_total = self.starts.saturating_mul(self.max_evaluations_per_start);
        for (field, n) in [
            ("optimiser.presearch_points", self.presearch_points),
            ("optimiser.starts × max_evaluations_per_start", starts_total),
            ("optimiser.finalists", self.finalists),
            ("optimiser.refine_evaluations", self.refine_evaluations),
        ] {
            if n > MAX_EVALUATIONS {
                return Err(invalid(
                    field,
                    format!("{n} evaluations is more than the {MAX_EVALUATIONS} accepted"),
                ));
            }
        }
        if self.finalists == 0 {
            return Err(invalid("optimiser.finalists", "must be ≥ 1"));
        }
        if !(self.x_tolerance > 0.0 && self.x_tolerance < 1.0) {
            return Err(invalid(
                "optimiser.x_tolerance",
                format!(
                    "{} must be in (0, 1) (a fraction of each range)",
                    self.x_tolerance
                ),
            ));
        }
        Ok(())
    }
}

/// The best design and every evaluation made.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SearchResult {
    /// The best feasible evaluation (at the highest fidelity that ran).
    pub best: Evaluation,
    /// Every evaluation, in the order made.
    pub evaluations: Vec<Evaluation>,
}

/// Feasibility-first order: smaller is better.
fn worse(a: &Outcome, b: &Outcome, sense: Sense) -> bool {
    match (a.feasible(), b.feasible()) {
        (true, false) => false,
        (false, true) => true,
        (false, false) => a.total_violation() > b.total_violation(),
        (true, true) => match sense {
            Sense::Maximise => a.objective < b.objective,
            Sense::Minimise => a.objective > b.objective,
        },
    }
}

fn failed(message: String) -> Outcome {
    Outcome {
        objective: f64::NAN,
        violations: vec![(format!("evaluation failed: {message}"), f64::INFINITY)],
        outputs: BTreeMap::new(),
    }
}

/// Latin hypercube of `n` points in the unit box of dimension `dim`.
fn latin_hypercube(n: usize, dim: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::new(seed);
    let mut points = vec![vec![0.0; dim]; n];
    for d in 0..dim {
        let mut strata: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            strata.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
        }
        for (p, s) in points.iter_mut().zip(strata) {
            p[d] = (s as f64 + 1.0 - rng.next_open01()) / n as f64;
        }
    }
    points
}

/// Evaluates designs at unit coordinates, memoised on the (rounded) design.
struct Evaluator<'a, F> {
    variables: &'a [Variable],
    model: &'a F,
    fidelity: &'a str,
    stage: &'static str,
    seen: HashMap<Vec<u64>, Outcome>,
    log: Vec<Evaluation>,
}

impl<F, M> Evaluator<'_, F>
where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    fn eval(&mut self, u: &[f64]) -> Outcome {
        let x: Vec<f64> = self
            .variables
            .iter()
            .zip(u)
            .map(|(v, &u)| v.at(u))
            .collect();
        let key: Vec<u64> = x.iter().map(|v| v.to_bits()).collect();
        if let Some(o) = self.seen.get(&key) {
            return o.clone();
        }
        let outcome = (self.model)(&x).unwrap_or_else(|e| failed(e.to_string()));
        self.seen.insert(key, outcome.clone());
        self.log.push(Evaluation {
            x,
            fidelity: self.fidelity.to_owned(),
            stage: self.stage,
            outcome: outcome.clone(),
        });
        outcome
    }
}

/// The start point and one step along each axis (backwards where a forward step would leave
/// the unit box), evaluated.
fn initial_simplex<F, M>(
    ev: &mut Evaluator<'_, F>,
    start: &[f64],
    step: f64,
) -> Vec<(Vec<f64>, Outcome)>
where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    let n = start.len();
    let mut simplex: Vec<(Vec<f64>, Outcome)> = Vec::with_capacity(n + 1);
    let o = ev.eval(start);
    simplex.push((start.to_vec(), o));
    for d in 0..n {
        let mut p = start.to_vec();
        p[d] += if p[d] + step <= 1.0 { step } else { -step };
        let o = ev.eval(&p);
        simplex.push((p, o));
    }
    simplex
}

/// Best vertex first, worst last (stable for ties).
fn sort_simplex(simplex: &mut [(Vec<f64>, Outcome)], sense: Sense) {
    simplex.sort_by(|a, b| {
        if worse(&a.1, &b.1, sense) {
            std::cmp::Ordering::Greater
        } else if worse(&b.1, &a.1, sense) {
            std::cmp::Ordering::Less
        } else {
            std::cmp::Ordering::Equal
        }
    });
}

/// One Nelder–Mead run from unit point `start`.
fn nelder_mead<F, M>(
    ev: &mut Evaluator<'_, F>,
    start: &[f64],
    (step, budget): (f64, usize),
    settings: &OptimiserSettings,
    sense: Sense,
) where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    let n = start.len();
    let clamp = |p: Vec<f64>| p.into_iter().map(|v| v.clamp(0.0, 1.0)).collect::<Vec<_>>();
    let mut simplex = initial_simplex(ev, start, step);
    let budget = ev.log.len() + budget;
    while ev.log.len() < budget {
        sort_simplex(&mut simplex, sense);
        let size = simplex[1..]
            .iter()
            .flat_map(|(p, _)| p.iter().zip(&simplex[0].0).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        if size < settings.x_tolerance {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|d| simplex[..n].iter().map(|(p, _)| p[d]).sum::<f64>() / n as f64)
            .collect();
        let along = |t: f64| {
            clamp(
                centroid
                    .iter()
                    .zip(&simplex[n].0)
                    .map(|(c, w)| c + t * (c - w))
                    .collect(),
            )
        };
        let xr = along(NM_REFLECT);
        let or = ev.eval(&xr);
        if worse(&simplex[0].1, &or, sense) {
            let xe = along(NM_EXPAND);
            let oe = ev.eval(&xe);
            simplex[n] = if worse(&or, &oe, sense) {
                (xe, oe)
            } else {
                (xr, or)
            };
        } else if worse(&simplex[n - 1].1, &or, sense) {
            simplex[n] = (xr, or);
        } else {
            let xc = along(-NM_CONTRACT);
            let oc = ev.eval(&xc);
            if worse(&simplex[n].1, &oc, sense) {
                simplex[n] = (xc, oc);
            } else {
                let best = simplex[0].0.clone();
                for v in simplex.iter_mut().skip(1) {
                    let p: Vec<f64> = best
                        .iter()
                        .zip(&v.0)
                        .map(|(b, x)| b + NM_SHRINK * (x - b))
                        .collect();
                    let o = ev.eval(&p);
                    *v = (p, o);
                }
            }
        }
    }
}

fn point_label(variables: &[Variable], x: &[f64]) -> String {
    variables
        .iter()
        .zip(x)
        .map(|(v, x)| format!("{} = {x}", v.name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The best evaluation of `evaluations` (feasibility first), or the infeasibility report.
fn best_of(evaluations: &[Evaluation], sense: Sense) -> Result<Evaluation> {
    let best = evaluations
        .iter()
        .reduce(|a, b| {
            if worse(&a.outcome, &b.outcome, sense) {
                b
            } else {
                a
            }
        })
        .ok_or_else(|| invalid("variables", "no design was evaluated"))?;
    if best.outcome.feasible() {
        Ok(best.clone())
    } else {
        Err(DesignError::Infeasible {
            constraints: best
                .outcome
                .violations
                .iter()
                .map(|v| v.0.clone())
                .collect(),
        })
    }
}

/// Pre-search + Nelder–Mead of `model` (design values → outcome) over `variables`.
/// A model error at a point is recorded as an infeasible evaluation (`evaluation failed: …`).
pub fn optimise<F, M>(
    variables: &[Variable],
    objective: &Objective,
    settings: &OptimiserSettings,
    fidelity: &str,
    model: &F,
) -> Result<SearchResult>
where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    if variables.is_empty() {
        return Err(invalid("variables", "at least one design variable"));
    }
    for v in variables {
        v.validate()?;
    }
    settings.validate()?;
    let sense = objective.sense;
    let lhs = latin_hypercube(settings.presearch_points, variables.len(), settings.seed);
    let pre: Vec<Evaluation> = lhs
        .par_iter()
        .map(|u| {
            let x: Vec<f64> = variables.iter().zip(u).map(|(v, &u)| v.at(u)).collect();
            Evaluation {
                outcome: model(&x).unwrap_or_else(|e| failed(e.to_string())),
                x,
                fidelity: fidelity.to_owned(),
                stage: "presearch",
            }
        })
        .collect();
    let mut order: Vec<usize> = (0..pre.len()).collect();
    order.sort_by(|&a, &b| {
        if worse(&pre[a].outcome, &pre[b].outcome, sense) {
            std::cmp::Ordering::Greater
        } else if worse(&pre[b].outcome, &pre[a].outcome, sense) {
            std::cmp::Ordering::Less
        } else {
            a.cmp(&b)
        }
    });
    let starts: Vec<Vec<f64>> = order
        .iter()
        .take(settings.starts)
        .map(|&i| lhs[i].clone())
        .collect();
    let runs: Vec<Vec<Evaluation>> = starts
        .par_iter()
        .map(|u| {
            let mut ev = Evaluator {
                variables,
                model,
                fidelity,
                stage: "nelder_mead",
                seen: HashMap::new(),
                log: Vec::new(),
            };
            let nm = (NM_INITIAL_STEP, settings.max_evaluations_per_start);
            nelder_mead(&mut ev, u, nm, settings, sense);
            ev.log
        })
        .collect();
    let mut evaluations = pre;
    evaluations.extend(runs.into_iter().flatten());
    let best = best_of(&evaluations, sense)?;
    Ok(SearchResult { best, evaluations })
}

/// Searches with `cheap` (fidelity label `cheap_name`), re-evaluates the best
/// [`OptimiserSettings::finalists`] distinct feasible designs with `full` (`full_name`), and
/// refines the best of them by a compass search on `full` (stage `refine`,
/// [`OptimiserSettings::refine_evaluations`]), and returns the best full-fidelity design. The
/// cheap model is used only to choose where the full model looks: every number of the optimum
/// is the full model's. A finalist infeasible at full fidelity is reported as such in the
/// evaluations; if all are, the error names their violated constraints.
pub fn multi_fidelity<C, F, M>(
    variables: &[Variable],
    objective: &Objective,
    settings: &OptimiserSettings,
    (cheap_name, cheap): (&str, &C),
    (full_name, full): (&str, &F),
) -> Result<SearchResult>
where
    C: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    let search = optimise(variables, objective, settings, cheap_name, cheap)?;
    let mut ranked: Vec<&Evaluation> = search
        .evaluations
        .iter()
        .filter(|e| e.outcome.feasible())
        .collect();
    ranked.sort_by(|a, b| {
        if worse(&a.outcome, &b.outcome, objective.sense) {
            std::cmp::Ordering::Greater
        } else if worse(&b.outcome, &a.outcome, objective.sense) {
            std::cmp::Ordering::Less
        } else {
            std::cmp::Ordering::Equal
        }
    });
    let distinct = |a: &[f64], b: &[f64]| {
        variables.iter().zip(a.iter().zip(b)).any(|(v, (a, b))| {
            (a - b).abs() > settings.x_tolerance * (v.upper - v.lower).max(f64::MIN_POSITIVE)
        })
    };
    let mut finalists: Vec<Vec<f64>> = Vec::new();
    for e in ranked {
        if finalists.len() == settings.finalists {
            break;
        }
        if finalists.iter().all(|f| distinct(f, &e.x)) {
            finalists.push(e.x.clone());
        }
    }
    let confirmed: Vec<Evaluation> = finalists
        .iter()
        .map(|x| Evaluation {
            outcome: full(x)
                .unwrap_or_else(|m| failed(format!("{m} at {}", point_label(variables, x)))),
            x: x.clone(),
            fidelity: full_name.to_owned(),
            stage: "confirm",
        })
        .collect();
    let confirmed_best = best_of(&confirmed, objective.sense)?;
    let refined = refine(
        variables,
        objective.sense,
        settings,
        (full_name, full),
        &confirmed,
        &confirmed_best.x,
    );
    let mut evaluations = search.evaluations;
    evaluations.extend(confirmed);
    evaluations.extend(refined);
    let full_evaluations: Vec<Evaluation> = evaluations
        .iter()
        .filter(|e| e.fidelity == full_name)
        .cloned()
        .collect();
    let best = best_of(&full_evaluations, objective.sense)?;
    Ok(SearchResult { best, evaluations })
}

/// The full-fidelity refinement: a compass search on `full` from the best confirmed finalist
/// `start` ([`compass_search`]), the finalists' outcomes reused. Its evaluations are tagged
/// `refine`.
fn refine<F, M>(
    variables: &[Variable],
    sense: Sense,
    settings: &OptimiserSettings,
    (full_name, full): (&str, &F),
    confirmed: &[Evaluation],
    start: &[f64],
) -> Vec<Evaluation>
where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    if settings.refine_evaluations == 0 {
        return Vec::new();
    }
    let mut ev = Evaluator {
        variables,
        model: full,
        fidelity: full_name,
        stage: "refine",
        seen: confirmed
            .iter()
            .map(|e| (e.x.iter().map(|v| v.to_bits()).collect(), e.outcome.clone()))
            .collect(),
        log: Vec::new(),
    };
    let unit: Vec<f64> = variables
        .iter()
        .zip(start)
        .map(|(v, x)| {
            if v.upper > v.lower {
                (x - v.lower) / (v.upper - v.lower)
            } else {
                0.0
            }
        })
        .collect();
    compass_search(&mut ev, &unit, settings, sense);
    ev.log
}

/// Compass search (Kolda, Lewis & Torczon 2003, SIAM Review 45(3) §3) in the unit box from
/// `start`: poll x ± s along each variable in turn (clamped into the box), move to the first
/// poll point that is better (feasibility first), else halve s; stop when s < x_tolerance or
/// after `refine_evaluations` new evaluations. s starts at [`REFINE_INITIAL_STEP`]. Unlike
/// Nelder–Mead it needs no smoothness (the full model's objective has steps in P where the
/// stick/slip regime changes) and, at convergence, no neighbour at ± the final step is better.
fn compass_search<F, M>(
    ev: &mut Evaluator<'_, F>,
    start: &[f64],
    settings: &OptimiserSettings,
    sense: Sense,
) where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    let mut best = (start.to_vec(), ev.eval(start));
    let mut step = REFINE_INITIAL_STEP;
    let stop = ev.log.len() + settings.refine_evaluations;
    while step >= settings.x_tolerance && ev.log.len() < stop {
        let mut improved = false;
        'poll: for d in 0..start.len() {
            for sign in [-1.0, 1.0] {
                let mut p = best.0.clone();
                p[d] = (p[d] + sign * step).clamp(0.0, 1.0);
                if p[d] == best.0[d] {
                    continue;
                }
                let o = ev.eval(&p);
                if worse(&best.1, &o, sense) {
                    best = (p, o);
                    improved = true;
                    break 'poll;
                }
                if ev.log.len() >= stop {
                    break 'poll;
                }
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
}

/// Sensitivity of the objective to one variable at a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariableSensitivity {
    /// Variable name (with unit).
    pub variable: String,
    /// Step used (variable's unit).
    pub step: f64,
    /// Objective at x − step and x + step (clamped into the bounds).
    pub objective_minus: f64,
    /// See `objective_minus`.
    pub objective_plus: f64,
    /// d objective / d variable by the (one- or two-sided) difference (objective unit per
    /// variable unit).
    pub derivative: f64,
    /// Relative sensitivity (x/f)·df/dx (dimensionless).
    pub elasticity: f64,
}

/// Finite-difference sensitivity of `model`'s objective at `x` to each variable, with steps of
/// `step_fraction` of each range (at least 1 for integers), one-sided at a bound or where the
/// neighbour violates a constraint (derivative 0 when both neighbours do).
pub fn local_sensitivity<F, M>(
    variables: &[Variable],
    x: &[f64],
    objective_at_x: f64,
    step_fraction: f64,
    model: &F,
) -> Result<Vec<VariableSensitivity>>
where
    F: Fn(&[f64]) -> std::result::Result<Outcome, M> + Sync,
    M: std::fmt::Display,
{
    variables
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let mut step = step_fraction * (v.upper - v.lower);
            if v.integer {
                step = step.round().max(1.0);
            }
            let at = |value: f64| -> Result<(f64, f64)> {
                let value = value.clamp(v.lower, v.upper);
                if value == x[k] {
                    return Ok((value, objective_at_x));
                }
                let mut y = x.to_vec();
                y[k] = value;
                let o = model(&y).map_err(|e| DesignError::Evaluation {
                    point: point_label(variables, &y),
                    message: e.to_string(),
                })?;
                // An infeasible neighbour (a constraint's boundary): one-sided difference.
                Ok(if o.feasible() {
                    (value, o.objective)
                } else {
                    (x[k], objective_at_x)
                })
            };
            let (xm, fm) = at(x[k] - step)?;
            let (xp, fp) = at(x[k] + step)?;
            let derivative = if xp > xm { (fp - fm) / (xp - xm) } else { 0.0 };
            Ok(VariableSensitivity {
                variable: v.name.clone(),
                step,
                objective_minus: fm,
                objective_plus: fp,
                derivative,
                elasticity: if objective_at_x != 0.0 {
                    x[k] / objective_at_x * derivative
                } else {
                    f64::NAN
                },
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluation_counts_beyond_the_bound_are_refused_before_any_search() {
        for settings in [
            OptimiserSettings {
                presearch_points: 1_000_000_000,
                ..Default::default()
            },
            OptimiserSettings {
                starts: usize::MAX,
                ..Default::default()
            },
            OptimiserSettings {
                finalists: MAX_EVALUATIONS + 1,
                ..Default::default()
            },
        ] {
            let err = settings.validate().unwrap_err().to_string();
            assert!(
                err.contains("optimiser.") && err.contains("100000"),
                "{err}"
            );
        }
        assert!(OptimiserSettings::default().validate().is_ok());
    }

    fn var(name: &str, lower: f64, upper: f64) -> Variable {
        Variable {
            name: name.into(),
            lower,
            upper,
            integer: false,
        }
    }

    /// Maximise −(x − 0.3)² − 4(y − 0.7)² + 1 on [0, 1]² (optimum (0.3, 0.7)), with the
    /// constraint x + y ≤ 1.5 inactive.
    fn toy(x: &[f64]) -> std::result::Result<Outcome, String> {
        let f = 1.0 - (x[0] - 0.3).powi(2) - 4.0 * (x[1] - 0.7).powi(2);
        let g = x[0] + x[1] - 1.5;
        Ok(Outcome {
            objective: f,
            violations: if g > 0.0 {
                vec![("sum_limit".into(), g)]
            } else {
                vec![]
            },
            outputs: BTreeMap::new(),
        })
    }

    fn maximise(output: &str) -> Objective {
        Objective {
            output: output.into(),
            sense: Sense::Maximise,
        }
    }

    #[test]
    fn the_optimiser_finds_a_known_optimum_within_its_tolerance() {
        let vars = [var("x_m", 0.0, 1.0), var("y_m", 0.0, 1.0)];
        let settings = OptimiserSettings::default();
        let r = optimise(&vars, &maximise("f"), &settings, "exact", &toy).unwrap();
        for (k, truth) in [0.3, 0.7].into_iter().enumerate() {
            assert!(
                (r.best.x[k] - truth).abs() <= settings.x_tolerance,
                "optimum coordinate {k}: {} vs {truth}",
                r.best.x[k]
            );
        }
        assert!(
            r.evaluations.len() < 250,
            "evaluations {}",
            r.evaluations.len()
        );
    }

    #[test]
    fn an_active_constraint_moves_the_optimum_onto_its_boundary() {
        // Optimum (0.9, 0.9) unconstrained; x + y ≤ 1.2 ⇒ (0.6, 0.6) on the line.
        let model = |x: &[f64]| -> std::result::Result<Outcome, String> {
            let g = x[0] + x[1] - 1.2;
            Ok(Outcome {
                objective: -(x[0] - 0.9).powi(2) - (x[1] - 0.9).powi(2),
                violations: if g > 0.0 {
                    vec![("sum_limit".into(), g)]
                } else {
                    vec![]
                },
                outputs: BTreeMap::new(),
            })
        };
        let vars = [var("x", 0.0, 1.0), var("y", 0.0, 1.0)];
        let settings = OptimiserSettings {
            x_tolerance: 1e-3,
            max_evaluations_per_start: 200,
            ..OptimiserSettings::default()
        };
        let r = optimise(&vars, &maximise("f"), &settings, "exact", &model).unwrap();
        assert!(r.best.x[0] + r.best.x[1] <= 1.2, "feasible optimum");
        assert!(
            (r.best.x[0] - 0.6).abs() < 0.02 && (r.best.x[1] - 0.6).abs() < 0.02,
            "constrained optimum {:?}",
            r.best.x
        );
    }

    #[test]
    fn an_infeasible_constraint_set_is_reported_naming_the_constraints() {
        let model = |x: &[f64]| -> std::result::Result<Outcome, String> {
            Ok(Outcome {
                objective: x[0],
                violations: vec![
                    ("min_gap_m".into(), 1.0 + x[0]),
                    ("max_preload_n".into(), 0.5),
                ],
                outputs: BTreeMap::new(),
            })
        };
        let e = optimise(
            &[var("x", 0.0, 1.0)],
            &maximise("f"),
            &OptimiserSettings::default(),
            "exact",
            &model,
        )
        .unwrap_err();
        assert_eq!(
            e,
            DesignError::Infeasible {
                constraints: vec!["min_gap_m".into(), "max_preload_n".into()]
            }
        );
        assert!(e.to_string().contains("min_gap_m, max_preload_n"), "{e}");
    }

    #[test]
    fn reversed_bounds_are_refused_naming_the_variable() {
        let e = optimise(
            &[var("post_diameter_m", 60e-6, 10e-6)],
            &maximise("f"),
            &OptimiserSettings::default(),
            "exact",
            &toy,
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("variables.post_diameter_m: bounds reversed"),
            "{e}"
        );
    }

    #[test]
    fn multi_fidelity_confirms_finalists_with_the_full_model_and_tags_them() {
        // The cheap model is biased (optimum at 0.35); the full model's optimum is 0.3.
        let cheap = |x: &[f64]| toy(&[x[0] - 0.05, x[1]]);
        let vars = [var("x_m", 0.0, 1.0), var("y_m", 0.0, 1.0)];
        let no_refinement = OptimiserSettings {
            refine_evaluations: 0,
            ..OptimiserSettings::default()
        };
        let r = multi_fidelity(
            &vars,
            &maximise("f"),
            &no_refinement,
            ("cheap", &cheap),
            ("full", &toy),
        )
        .unwrap();
        assert_eq!(r.best.fidelity, "full", "fidelity of the optimum");
        assert_eq!(r.best.stage, "confirm");
        let full = r
            .evaluations
            .iter()
            .filter(|e| e.fidelity == "full")
            .count();
        assert!((1..=3).contains(&full), "finalists confirmed: {full}");
        assert!(
            (r.best.x[0] - 0.35).abs() < 0.02,
            "the confirmed design is a cheap-model finalist"
        );
        let exact = toy(&r.best.x).unwrap().objective;
        assert_eq!(
            r.best.outcome.objective, exact,
            "confirmed objective is the full model's"
        );
    }

    #[test]
    fn the_full_fidelity_refinement_removes_the_cheap_models_bias() {
        // The cheap model's optimum is at x = 0.35; the full model's at (0.3, 0.7).
        let cheap = |x: &[f64]| toy(&[x[0] - 0.05, x[1]]);
        let vars = [var("x_m", 0.0, 1.0), var("y_m", 0.0, 1.0)];
        let settings = OptimiserSettings {
            refine_evaluations: 40,
            ..OptimiserSettings::default()
        };
        let r = multi_fidelity(
            &vars,
            &maximise("f"),
            &settings,
            ("cheap", &cheap),
            ("full", &toy),
        )
        .unwrap();
        assert_eq!(r.best.fidelity, "full", "fidelity of the refined optimum");
        assert_eq!(
            r.best.stage, "refine",
            "the refinement improved on the finalists"
        );
        for (k, truth) in [0.3, 0.7].into_iter().enumerate() {
            assert!(
                (r.best.x[k] - truth).abs() <= settings.x_tolerance,
                "refined optimum coordinate {k}: {} vs the full model's {truth}",
                r.best.x[k]
            );
        }
        assert!(
            r.evaluations
                .iter()
                .filter(|e| e.stage == "refine")
                .all(|e| e.fidelity == "full"),
            "refinement evaluations are full-fidelity"
        );
    }

    #[test]
    fn integer_variables_take_whole_values() {
        let model = |x: &[f64]| -> std::result::Result<Outcome, String> {
            Ok(Outcome {
                objective: -(x[0] - 37.4).powi(2),
                violations: vec![],
                outputs: BTreeMap::new(),
            })
        };
        let v = Variable {
            name: "posts_per_side".into(),
            lower: 10.0,
            upper: 200.0,
            integer: true,
        };
        let r = optimise(
            &[v],
            &maximise("f"),
            &OptimiserSettings::default(),
            "exact",
            &model,
        )
        .unwrap();
        assert_eq!(r.best.x[0], 37.0, "posts per side");
        assert!(
            r.evaluations.iter().all(|e| e.x[0].fract() == 0.0),
            "whole numbers only"
        );
    }

    #[test]
    fn local_sensitivity_recovers_the_gradient_of_a_linear_model() {
        let model = |x: &[f64]| -> std::result::Result<Outcome, String> {
            Ok(Outcome {
                objective: 3.0 * x[0] - 2.0 * x[1],
                violations: vec![],
                outputs: BTreeMap::new(),
            })
        };
        let vars = [var("a", 0.0, 1.0), var("b", 0.0, 1.0)];
        let s = local_sensitivity(&vars, &[0.5, 1.0], 3.0 * 0.5 - 2.0, 0.05, &model).unwrap();
        assert!((s[0].derivative - 3.0).abs() < 1e-12, "∂f/∂a");
        assert!(
            (s[1].derivative + 2.0).abs() < 1e-12,
            "∂f/∂b one-sided at the bound"
        );
    }
}
