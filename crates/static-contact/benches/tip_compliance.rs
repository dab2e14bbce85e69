//! The default strip's tangential tip compliance: partial forward solves on
//! the disk unknowns' elimination-tree paths (`BodyCompliance::tangential_compliance`) against
//! full solves with the same factor (`tangential_compliance_by_solves`, SOLVE_BATCH_COLUMNS
//! right-hand sides at a time), with the factorisation for scale. Wall and CPU time
//! (user + sys of the process, Linux), multiply–add counts, and the relative difference of the
//! two results.
//!
//! ```sh
//! RAYON_NUM_THREADS=1 cargo bench -p static-contact --bench tip_compliance   # and =2
//! ```
//! The default strip's mesh is generated (gmsh, ≈ 10 s) or found in the mesh cache first.
//! `--profile test` (opt-level 2, dependencies 3) gives the same kernels' speed without a
//! release build. Prints one `name wall_s cpu_s multiply_adds` line per stage.

use std::time::Instant;

use nalgebra::DMatrix;
use static_contact::mesh_source::resolve_mesh;
use static_contact::{StaticParams, prepare_strip};

/// User + system CPU time of this process (s), from /proc/self/stat (clock ticks of 1/100 s).
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after_name = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after_name.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    (ticks(11) + ticks(12)) / 100.0
}

/// Runs `f` and prints its wall and CPU time with `flops` multiply–adds.
fn timed<T>(name: &str, flops: impl Fn(&T) -> f64, f: impl FnOnce() -> T) -> T {
    let (wall, cpu) = (Instant::now(), cpu_s());
    let out = f();
    println!(
        "{name} {:.3} {:.2} {:.3e}",
        wall.elapsed().as_secs_f64(),
        cpu_s() - cpu,
        flops(&out)
    );
    out
}

fn relative_difference(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

fn main() {
    // Mesh ahead (gmsh) or find the mesh in the cache: the timed runs below read it from there.
    let params = StaticParams::default();
    resolve_mesh(&params).expect("default strip mesh (gmsh installed?)");
    println!(
        "# name wall_s cpu_s multiply_adds (rayon threads {}, load average {})",
        rayon::current_num_threads(),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .trim()
    );
    let strip = timed(
        "assembly_and_factor",
        |s: &static_contact::PreparedStrip| s.model.slider.stats.factor_flops,
        || prepare_strip(&params).expect("default strip"),
    );
    let slider = &strip.model.slider;
    let stats = slider.stats;
    println!(
        "# unknowns {}, factor values {}, factor {:.3} s ({:.3} s analysis)",
        stats.reduced_unknowns, stats.factor_nnz, stats.factor_s, stats.analysis_s
    );
    let (partial, work) = timed(
        "tangential_partial_forward_solves",
        |(_, w): &(_, elastic_fem::sparse::InverseGramStats)| w.flops,
        || {
            slider
                .tangential_compliance_with_work()
                .expect("partial solves")
        },
    );
    println!(
        "# supernodes visited {} of {}, Y values held {} ({:.1} MB)",
        work.supernodes_visited,
        work.supernodes_total,
        work.stored_values,
        work.stored_values as f64 * 8e-6
    );
    let posts = partial.tangential_m_per_n.nrows() as f64;
    let full = timed(
        "tangential_full_solves",
        |_| 2.0 * posts * stats.factor_nnz as f64,
        || {
            slider
                .tangential_compliance_by_solves()
                .expect("full solves")
        },
    );
    println!(
        "# relative difference partial vs full: tangential {:.2e}, cross {:.2e}",
        relative_difference(&partial.tangential_m_per_n, &full.tangential_m_per_n),
        relative_difference(
            &partial.normal_from_tangential_m_per_n,
            &full.normal_from_tangential_m_per_n
        )
    );
}
