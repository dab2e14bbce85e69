//! Sweeps on a cluster: `--shard K/N` runs a deterministic share of the points, `--merge` (or the
//! shard that saves the last point) collects every saved point into `results.csv` and the charts.
//!
//! Split rule: point `i` (1-based, sweep order) belongs to shard `((i − 1) mod N) + 1`, so shard
//! K runs points K, K+N, K+2N, … The rule depends only on the sweep file and N, so every process
//! of a job array agrees on it without talking to the others, and the shards differ by at most
//! one point. Neighbouring points differ in the fastest-varying grid key and cost about the same,
//! so dealing them round-robin balances the work better than contiguous blocks (a block of the
//! costliest variant would land on one shard). The FEM condensations, which depend on the slider
//! geometry and not on the preload, are not split by this rule: the first shard to lock a
//! geometry condenses it for every shard ([`super::locks`]), so none is run twice.
//!
//! Merged results equal those of an unsharded run: the rows are read from the saved points in
//! sweep order and written by the same functions; only `wall_time_s`, a measurement, differs
//! between any two runs.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::Serialize;

use super::error::SweepRunError;
use super::run::{Prepared, prepare};
use super::{PointRow, SweepFile, SweepOutcome};
use crate::pipeline::RunControl;

/// Shard `index` of `count` (1-based): the points `index`, `index + count`, … of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Shard {
    /// K, 1-based.
    pub index: usize,
    /// N, the number of shards.
    pub count: usize,
}

impl Shard {
    /// Whether point `i` (0-based, sweep order) belongs to this shard (never, for N = 0).
    pub fn owns(&self, i: usize) -> bool {
        self.count > 0 && i % self.count + 1 == self.index
    }

    /// Refuse K outside 1..=N and more shards than the sweep's `points`.
    fn check(&self, sweep: &str, points: usize) -> Result<(), SweepRunError> {
        let refuse = |message: String| SweepRunError::Shard {
            shard: self.to_string(),
            message,
        };
        if self.count == 0 {
            return Err(refuse("N must be at least 1".into()));
        }
        if self.index == 0 || self.index > self.count {
            return Err(refuse(format!(
                "shard index {} is outside 1..={}: the {points} points of sweep {sweep} go to shards 1..={} (shard K runs points K, K+{}, …)",
                self.index, self.count, self.count, self.count
            )));
        }
        if self.count > points {
            return Err(refuse(format!(
                "sweep {sweep} has {points} points, fewer than {} shards: shards {}..={} would run nothing; use N ≤ {points}",
                self.count,
                points + 1,
                self.count
            )));
        }
        Ok(())
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `K/N`, two whole numbers; the range is checked against the sweep by [`run_shard`].
impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let parse = |part: &str| part.trim().parse::<usize>().ok();
        match text.split_once('/').map(|(k, n)| (parse(k), parse(n))) {
            Some((Some(index), Some(count))) => Ok(Shard { index, count }),
            _ => Err(format!(
                "\"{text}\" is not K/N (shard K of N, whole numbers, e.g. 2/4)"
            )),
        }
    }
}

/// Outcome of one shard.
#[derive(Debug, Clone, Serialize)]
pub struct ShardOutcome {
    /// Which shard ran.
    pub shard: Shard,
    /// Results folder of the sweep.
    pub folder: PathBuf,
    /// Rows of this shard's points, in sweep order.
    pub rows: Vec<PointRow>,
    /// Points this shard owns.
    pub points: usize,
    /// Of them, points that were already saved (resumed).
    pub resumed: usize,
    /// Points that failed: (overrides, error).
    pub failures: Vec<(String, String)>,
    /// FEM condensations this shard ran (for any shard's points).
    pub condensations: usize,
    /// Points of the whole sweep not saved yet (by any shard) when this shard finished.
    pub missing: usize,
    /// The merged sweep, if this shard found every point saved.
    pub merged: Option<SweepOutcome>,
}

/// Run the share `shard` of `sweep` into `out_dir/<sweep name>/` with `jobs` threads (None: all
/// cores), then merge if every point of the sweep is saved.
pub fn run_shard(
    sweep: &SweepFile,
    out_dir: &Path,
    jobs: Option<usize>,
    shard: Shard,
) -> Result<ShardOutcome, SweepRunError> {
    let prepared = prepare(sweep, out_dir, jobs)?;
    shard.check(&sweep.name, prepared.points.len())?;
    let mine: Vec<usize> = (0..prepared.points.len())
        .filter(|&i| shard.owns(i))
        .collect();
    let run = prepared.run_points(&mine, jobs, shard.index - 1, &RunControl::none())?;
    let missing = missing_points(&prepared).len();
    let merged = match missing {
        0 => Some(merge_prepared(&prepared)?),
        _ => None,
    };
    Ok(ShardOutcome {
        shard,
        folder: prepared.folder,
        rows: run.rows,
        points: mine.len(),
        resumed: run.resumed,
        failures: run.failures,
        condensations: run.condensations,
        missing,
        merged,
    })
}

/// Collect the saved points of every shard of `sweep` into `results.csv` and the charts. Runs no
/// point; refuses (writing nothing) while any point is not saved, naming them.
pub fn merge_sweep(sweep: &SweepFile, out_dir: &Path) -> Result<SweepOutcome, SweepRunError> {
    let prepared = prepare(sweep, out_dir, None)?;
    let missing = missing_points(&prepared);
    if !missing.is_empty() {
        return Err(SweepRunError::MissingPoints {
            sweep: sweep.name.clone(),
            folder: prepared.points_dir.clone(),
            missing,
            total: prepared.points.len(),
        });
    }
    merge_prepared(&prepared)
}

/// Points (1-based number, overrides) of the sweep without a saved result.
fn missing_points(prepared: &Prepared) -> Vec<(usize, String)> {
    (0..prepared.points.len())
        .filter(|&i| prepared.saved(i).is_none())
        .map(|i| (i + 1, prepared.points[i].overrides.join(" ")))
        .collect()
}

/// Write the results of a sweep whose points are all saved. Shards finishing together may both
/// merge: each writes the same bytes atomically, one after the other (the lock
/// `OUT/.cache/locks/merge-<sweep name>.lock`, outside the results folder).
fn merge_prepared(prepared: &Prepared) -> Result<SweepOutcome, SweepRunError> {
    let lock = super::locks::lock_exclusive(
        &prepared.cache,
        &format!("merge-{}.lock", prepared.sweep.name),
    )?;
    let rows: Vec<PointRow> = (0..prepared.points.len())
        .filter_map(|i| prepared.saved(i))
        .collect();
    let files = prepared.write_results(&rows)?;
    drop(lock);
    Ok(SweepOutcome {
        folder: prepared.folder.clone(),
        resumed: rows.len(),
        rows,
        failures: Vec::new(),
        files,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_belongs_to_exactly_one_shard() {
        for count in 1..=5 {
            for i in 0..17 {
                let owners: Vec<usize> = (1..=count)
                    .filter(|&index| Shard { index, count }.owns(i))
                    .collect();
                assert_eq!(owners, vec![i % count + 1], "owner of point {i} of {count}");
            }
        }
    }

    #[test]
    fn shard_text_is_k_slash_n() {
        assert_eq!("2/4".parse::<Shard>(), Ok(Shard { index: 2, count: 4 }));
        for bad in ["2", "a/4", "2/-1", "2/4/1", ""] {
            let error = bad.parse::<Shard>().unwrap_err();
            assert!(error.contains("is not K/N"), "{bad}: {error}");
        }
    }

    #[test]
    fn shard_index_outside_one_to_n_names_the_split() {
        let error = Shard { index: 4, count: 3 }
            .check("s", 12)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with("--shard 4/3: shard index 4 is outside 1..=3"),
            "{error}"
        );
        assert!(error.contains("12 points"), "{error}");
        let error = Shard { index: 0, count: 3 }.check("s", 12).unwrap_err();
        assert!(error.to_string().contains("outside 1..=3"), "{error}");
        let error = Shard { index: 1, count: 5 }.check("s", 2).unwrap_err();
        assert!(error.to_string().contains("use N ≤ 2"), "{error}");
        assert!(Shard { index: 2, count: 2 }.check("s", 2).is_ok());
    }
}
