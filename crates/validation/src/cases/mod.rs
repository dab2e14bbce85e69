//! Every validation study as a case of one command, `sawdrive validate <case> --level L`.
//!
//! A case runs at one of three [`Level`]s: `full` (the study behind the committed numbers of
//! `validation/<case>/`), `quick` (every code path of `full` — every solver `auto` can pick,
//! every stability case, every model — on smaller meshes, ≤ 5 min on 2 cores) and `smoke` (a
//! few seconds; all cases together ≤ 3 min). Each case returns [`Check`]s: a value, its
//! reference, a tolerance, the rule comparing them, whether it passed and where the reference
//! comes from. `--json` prints them as `{"checks": [...]}` ([`checks_json`]), and
//! [`summary_markdown`] writes `validation/SUMMARY.md`.
//!
//! The cases ([`CASES`]) and their modules: `springs` ([`springs`]), `stick-slip`
//! ([`stick_slip`]), `static-contact` ([`static_contact`]), `whole-slider` ([`whole_slider`]),
//! `coupled-dynamics` ([`coupled_dynamics`]), `paper-figures` ([`paper_figures`], through a
//! pipeline runner the `sawdrive` command injects), `design` ([`design`]), `fem-peers`
//! ([`fem_peers`]). Each writes `results/` and `figures/` (SVG; [`drop_png_duplicates`]) into its
//! output folder, the layout of `validation/<case>/`.

pub mod coupled_dynamics;
pub mod coupled_strips;
pub mod design;
pub mod fem_peers;
pub mod paper_figures;
pub mod springs;
pub mod static_contact;
pub mod stick_slip;
pub mod whole_slider;
pub mod whole_slider_bands;

use serde::{Deserialize, Serialize};

/// How much of a study runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// Seconds: the pipeline end to end on the coarsest inputs.
    Smoke,
    /// Every code path of `full` on smaller meshes (≤ 5 min per case on 2 cores).
    Quick,
    /// The committed study.
    Full,
}

impl Level {
    /// Parses `smoke`, `quick` or `full`.
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "smoke" => Some(Self::Smoke),
            "quick" => Some(Self::Quick),
            "full" => Some(Self::Full),
            _ => None,
        }
    }

    /// The lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Smoke => "smoke",
            Self::Quick => "quick",
            Self::Full => "full",
        }
    }
}

/// How a check compares its value with its reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// |value / reference − 1| ≤ tolerance.
    Relative,
    /// value ≤ reference (tolerance unused, 0).
    AtMost,
    /// value ≥ reference (tolerance unused, 0).
    AtLeast,
}

/// One checked quantity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// Case name (e.g. `springs`).
    pub case: String,
    /// What is checked, e.g. `k_pn (si, a = 10 um): FEM / formula`.
    pub quantity: String,
    /// The computed value.
    pub value: f64,
    /// The reference value (or bound, see `rule`).
    pub reference: f64,
    /// Relative tolerance of a [`Rule::Relative`] check (0 for bounds).
    pub tolerance: f64,
    /// Whether the check holds.
    pub pass: bool,
    /// Where the reference comes from (formula, paper, README section).
    pub source: String,
    /// How `value` is compared with `reference`.
    pub rule: Rule,
}

impl Rule {
    /// Whether `value` passes against `reference` under this rule.
    fn holds(self, value: f64, reference: f64, tolerance: f64) -> bool {
        match self {
            Rule::Relative => (value / reference - 1.0).abs() <= tolerance,
            Rule::AtMost => value <= reference,
            Rule::AtLeast => value >= reference,
        }
    }
}

impl Check {
    /// A check of `value` against `reference` under `rule`; `pass` follows from the rule.
    fn new(
        case: &str,
        quantity: impl Into<String>,
        (value, reference, tolerance): (f64, f64, f64),
        source: impl Into<String>,
        rule: Rule,
    ) -> Self {
        Self {
            case: case.into(),
            quantity: quantity.into(),
            value,
            reference,
            tolerance,
            pass: rule.holds(value, reference, tolerance),
            source: source.into(),
            rule,
        }
    }

    /// |value / reference − 1| ≤ tolerance.
    pub fn relative(
        case: &str,
        quantity: impl Into<String>,
        value: f64,
        reference: f64,
        tolerance: f64,
        source: impl Into<String>,
    ) -> Self {
        let numbers = (value, reference, tolerance);
        Self::new(case, quantity, numbers, source, Rule::Relative)
    }

    /// value ≤ bound.
    pub fn at_most(
        case: &str,
        quantity: impl Into<String>,
        value: f64,
        bound: f64,
        source: impl Into<String>,
    ) -> Self {
        Self::new(case, quantity, (value, bound, 0.0), source, Rule::AtMost)
    }

    /// value ≥ bound.
    pub fn at_least(
        case: &str,
        quantity: impl Into<String>,
        value: f64,
        bound: f64,
        source: impl Into<String>,
    ) -> Self {
        Self::new(case, quantity, (value, bound, 0.0), source, Rule::AtLeast)
    }

    /// One line naming the check and its numbers (for a failure message).
    pub fn line(&self) -> String {
        let comparison = match self.rule {
            Rule::Relative => format!(
                "{:e} vs reference {:e} (relative tolerance {:e})",
                self.value, self.reference, self.tolerance
            ),
            Rule::AtMost => format!("{:e}, must be ≤ {:e}", self.value, self.reference),
            Rule::AtLeast => format!("{:e}, must be ≥ {:e}", self.value, self.reference),
        };
        format!(
            "{}: {}: {comparison} [{}]",
            self.case, self.quantity, self.source
        )
    }
}

/// The outcome of one case at one level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseOutcome {
    /// Case name.
    pub case: String,
    /// Level run.
    pub level: Level,
    /// Checks (empty when skipped).
    pub checks: Vec<Check>,
    /// Why the case did not run (peers not installed, not ported), else `None`.
    pub skipped: Option<String>,
    /// Wall time (s).
    pub wall_s: f64,
}

impl CaseOutcome {
    /// The first failing check, if any.
    pub fn first_failure(&self) -> Option<&Check> {
        self.checks.iter().find(|c| !c.pass)
    }
}

/// A case of `sawdrive validate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CaseInfo {
    /// Name on the command line and folder `validation/<name>/`.
    pub name: &'static str,
    /// What it validates.
    pub description: &'static str,
    /// The command that regenerates the committed study today, for cases whose checks are not
    /// yet run by `sawdrive validate` (`None`: it runs them).
    pub regenerate: Option<&'static str>,
    /// How long the full level takes on 2 cores (release build, load ≈ 3), measured; the summary
    /// names it beside a section run at another level.
    pub full_level_time: &'static str,
}

/// Every case, in the order `validate all` runs them.
pub const CASES: &[CaseInfo] = &[
    CaseInfo {
        name: "springs",
        description: "FEM stiffness of a rigid punch on a half-space against the four Johnson springs; convergence, truncation, work-precision, stability (locking, floating punch, distorted meshes), both solver paths",
        regenerate: None,
        full_level_time: "231 s with the punch meshes cached, ≈ 14 min generating them",
    },
    CaseInfo {
        name: "stick-slip",
        description: "integrators of the stick/slip post model: work-precision against the closed-form reference, transient against period average, stability maps, the paper's trends",
        regenerate: None,
        full_level_time: "15 s",
    },
    CaseInfo {
        name: "static-contact",
        description: "static contact: one post's body compliance (static-contact solver) against k_pn and k_sn, converging with the mesh; the strip, preload, diameter and count sections by its example",
        regenerate: None,
        full_level_time: "3 s with the punch meshes cached; the first run meshes them with gmsh",
    },
    CaseInfo {
        name: "whole-slider",
        description: "whole-slider static contact: lattice operator against the pairwise sum, force and moment balance of every preload mechanism, eta against scatter, tilt and bow, edge loading, the committed study and the strip FEM",
        regenerate: None,
        full_level_time: "38 s",
    },
    CaseInfo {
        name: "coupled-dynamics",
        description: "coupled slider dynamics: work-precision of the coupled integrator, energy balance, whole rows against the FEM strip's, the energy-conserving wave",
        regenerate: None,
        full_level_time: "28 s with the whole rows' FEM cache filled; the first run meshes and factors eight whole-row and eight short strips",
    },
    CaseInfo {
        name: "paper-figures",
        description: "the paper's figures 7-12 through the whole pipeline: trends of stall thrust and no-load speed against preload, post count, diameter; the paper's stated numbers",
        regenerate: None,
        full_level_time: "0.4 s with the FEM cache filled, ≈ 1.5 min cold",
    },
    CaseInfo {
        name: "design",
        description: "the optimiser on known optima (unconstrained, active constraint, integer variable) and the convergence of the UQ statistics",
        regenerate: None,
        full_level_time: "0.05 s",
    },
    CaseInfo {
        name: "fem-peers",
        description: "elastic-fem against peer FEM codes (scikit-fem, CalculiX) on the punch: agreement and time; needs the peers installed",
        regenerate: None,
        full_level_time: "minutes, with the peers installed (not measured here)",
    },
];

/// Removes every PNG under `dir` (recursively) that has an SVG of the same stem beside it: a
/// case's figures are SVG (`validation/<case>/figures/`), the chart writer draws both; a PNG
/// without an SVG (a post-force map whose SVG is too large) stays. Returns the number removed.
pub fn drop_png_duplicates(dir: &std::path::Path) -> std::io::Result<usize> {
    let mut removed = 0;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(0);
    };
    for entry in entries {
        let path = entry?.path();
        if path.is_dir() {
            removed += drop_png_duplicates(&path)?;
        } else if path.extension().is_some_and(|e| e == "png")
            && path.with_extension("svg").is_file()
        {
            std::fs::remove_file(&path)?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// The case named `name`.
pub fn case(name: &str) -> Option<&'static CaseInfo> {
    CASES.iter().find(|c| c.name == name)
}

/// The outcome of a case whose checks `sawdrive validate` does not run yet: skipped, naming the
/// command that regenerates it.
pub fn not_ported(info: &CaseInfo, level: Level) -> CaseOutcome {
    CaseOutcome {
        case: info.name.into(),
        level,
        checks: Vec::new(),
        skipped: Some(format!(
            "checks not yet run by `sawdrive validate`; the study is regenerated by: {}",
            info.regenerate.unwrap_or("(none)")
        )),
        wall_s: 0.0,
    }
}

/// `{"checks": [...]}` of every outcome's checks, plus the skipped cases.
pub fn checks_json(outcomes: &[CaseOutcome]) -> String {
    #[derive(Serialize)]
    struct Skipped<'a> {
        case: &'a str,
        level: Level,
        reason: &'a str,
    }
    #[derive(Serialize)]
    struct Out<'a> {
        checks: Vec<&'a Check>,
        skipped: Vec<Skipped<'a>>,
    }
    let out = Out {
        checks: outcomes.iter().flat_map(|o| &o.checks).collect(),
        skipped: outcomes
            .iter()
            .filter_map(|o| {
                o.skipped.as_deref().map(|reason| Skipped {
                    case: &o.case,
                    level: o.level,
                    reason,
                })
            })
            .collect(),
    };
    serde_json::to_string_pretty(&out).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

/// Text as one Markdown table cell: `|` escaped (quantities such as |Σ f ξ| / P contain it).
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

/// Markdown table of every check (quantity, value, reference, tolerance, pass, level, commit),
/// one section per case; skipped cases say why. The whole file from these outcomes alone
/// ([`update_summary`] without a previous file).
pub fn summary_markdown(outcomes: &[CaseOutcome], commit: &str) -> String {
    update_summary(None, outcomes, commit)
}

/// `validation/SUMMARY.md` with the sections of the cases in `outcomes` written anew and every
/// other case's section of `previous` kept as it was (each row names the level and commit it
/// was run at), in the order of [`CASES`]; the totals count every section. So each case can be
/// run at the level its cost allows (`sawdrive validate <case> --level full --summary FILE`)
/// and the table gathers them.
pub fn update_summary(previous: Option<&str>, outcomes: &[CaseOutcome], commit: &str) -> String {
    let mut sections: Vec<(String, String)> = previous.map(previous_sections).unwrap_or_default();
    for o in outcomes {
        let text = case_section(o, commit);
        match sections.iter_mut().find(|(case, _)| *case == o.case) {
            Some(section) => section.1 = text,
            None => sections.push((o.case.clone(), text)),
        }
    }
    let rank = |case: &str| {
        CASES
            .iter()
            .position(|c| c.name == case)
            .unwrap_or(CASES.len())
    };
    sections.sort_by_key(|(case, _)| rank(case));
    let rows: Vec<&str> = sections
        .iter()
        .flat_map(|(_, text)| text.lines())
        .filter(|l| l.starts_with("| ") && !l.starts_with("| quantity |"))
        .collect();
    let failed = rows.iter().filter(|l| l.contains("| **NO** |")).count();
    let skipped = sections
        .iter()
        .filter(|(_, text)| text.contains("\nSkipped: "))
        .count();
    let mut s = String::from("# Validation summary\n\n");
    s += &wrap(
        "Generated by `sawdrive validate <case> --level <level> --summary validation/SUMMARY.md`, \
         which rewrites the sections of the cases it runs and keeps the others \
         (`validate all` rewrites every section); do not edit by hand. Each section names the \
         level it was run at, and each row the level and commit; the sources of the references \
         are listed under each table. Rules: `relative` passes when \
         `|value / reference − 1| ≤ tolerance`; `at_most` / `at_least` compare the value with \
         the reference as a bound.",
        "",
    );
    s += &format!(
        "\n{} checks, {failed} failing, {skipped} case(s) skipped.\n\n",
        rows.len()
    );
    for (_, text) in &sections {
        s += text;
    }
    s
}

/// The `## <case> (…)` sections of a summary, by case name, each with its text up to the next.
fn previous_sections(text: &str) -> Vec<(String, String)> {
    let mut sections: Vec<(String, String)> = Vec::new();
    for line in text.split_inclusive('\n') {
        if let Some(heading) = line.strip_prefix("## ") {
            let case = heading.split_whitespace().next().unwrap_or_default();
            sections.push((case.to_string(), String::new()));
        }
        if let Some((_, body)) = sections.last_mut() {
            *body += line;
        }
    }
    for (_, body) in &mut sections {
        if !body.ends_with("\n\n") {
            *body += "\n";
        }
    }
    sections
}

/// Width at which the summary's prose is wrapped (characters). A Markdown line of the summary
/// stays far below 400 characters: prose and source lists are wrapped, and a table row holds the
/// quantity, the numbers and a source number, not the source's text.
pub const SUMMARY_WIDTH: usize = 100;

/// `text` wrapped at [`SUMMARY_WIDTH`] characters, every line after the first indented by
/// `indent`, ending with a newline. Spaces inside a `code span` do not break, so a command
/// stays on one line.
fn wrap(text: &str, indent: &str) -> String {
    let mut words: Vec<String> = Vec::new();
    let mut in_code = false;
    for word in text.split_whitespace() {
        match words.last_mut() {
            Some(last) if in_code => {
                last.push(' ');
                last.push_str(word);
            }
            _ => words.push(word.to_string()),
        }
        if word.matches('`').count() % 2 == 1 {
            in_code = !in_code;
        }
    }
    let mut out = String::new();
    let mut line = String::new();
    for word in words {
        let width = line.chars().count() + 1 + word.chars().count();
        if !line.trim().is_empty() && width > SUMMARY_WIDTH {
            out += line.trim_end();
            out.push('\n');
            line = indent.to_string();
        }
        if !line.trim().is_empty() {
            line.push(' ');
        }
        line += &word;
    }
    out += line.trim_end();
    out.push('\n');
    out
}

/// One case's section: heading with level and wall time, the command that runs the full level
/// when it ran at another, then its table (or why it was skipped) and the numbered sources its
/// rows cite.
fn case_section(o: &CaseOutcome, commit: &str) -> String {
    let mut s = format!(
        "## {} ({} level, {:.0} s, commit `{commit}`)\n\n",
        o.case,
        o.level.name(),
        o.wall_s
    );
    if o.level != Level::Full {
        let cost = case(&o.case).map_or("", |c| c.full_level_time);
        s += &wrap(
            &format!(
                "Run at the {} level (`sawdrive validate {} --level {} --summary \
                 validation/SUMMARY.md`); the full level, {cost}, is `sawdrive validate {} --level \
                 full --summary validation/SUMMARY.md`.",
                o.level.name(),
                o.case,
                o.level.name(),
                o.case
            ),
            "",
        );
        s.push('\n');
    }
    if let Some(reason) = &o.skipped {
        s += &wrap(&format!("Skipped: {reason}"), "");
        s.push('\n');
        return s;
    }
    let mut sources: Vec<&str> = Vec::new();
    s += "| quantity | value | reference | tolerance | rule | pass | level | commit | source |\n";
    s += "|---|---|---|---|---|---|---|---|---|\n";
    for c in &o.checks {
        let rule = match c.rule {
            Rule::Relative => "relative",
            Rule::AtMost => "at_most",
            Rule::AtLeast => "at_least",
        };
        let source = match sources.iter().position(|x| *x == c.source) {
            Some(k) => k + 1,
            None => {
                sources.push(&c.source);
                sources.len()
            }
        };
        s += &format!(
            "| {} | {:.6e} | {:.6e} | {} | {rule} | {} | {} | `{commit}` | [{source}] |\n",
            cell(&c.quantity),
            c.value,
            c.reference,
            if c.rule == Rule::Relative {
                format!("{:.1e}", c.tolerance)
            } else {
                "—".into()
            },
            if c.pass { "yes" } else { "**NO**" },
            o.level.name(),
        );
    }
    if !sources.is_empty() {
        s += "\nSources:\n\n";
        for (k, source) in sources.iter().enumerate() {
            let label = format!("{}. ", k + 1);
            let indent = " ".repeat(label.len());
            s += &wrap(&format!("{label}{source}"), &indent);
        }
    }
    s += "\n";
    s
}

/// Writes `text` to `path`, creating its folder (a case's CSV results).
pub(crate) fn write_text(
    path: &std::path::Path,
    text: &str,
) -> Result<(), crate::error::ValidationError> {
    let io = |p: &std::path::Path, source: std::io::Error| crate::error::ValidationError::Io {
        path: p.to_path_buf(),
        source,
    };
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
    }
    std::fs::write(path, text).map_err(|e| io(path, e))
}
