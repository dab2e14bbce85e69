//! Wall time of η for the default scene (100 × 100 posts of 20 µm, 40 N, 4 phases, Tet10 strip
//! of the whole post row, half-space stator), from a cached mesh, against the 10-post strip of
//! the same slider as a reference measured in the same run; and the gmsh meshing of the default
//! strip that a cold start adds (into a fresh directory each time).
//!
//! ```sh
//! cargo bench -p static-contact --bench default_eta     # ≈ 10 runs of ≈ 30 s + 10 of ≈ 8 s: run on a quiet machine
//! ```
//! For the η timings the mesh is generated (gmsh) or found in the cache before timing starts.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use static_contact::mesh_source::{generate_mesh, resolve_mesh, strip_mesh_parameters};
use static_contact::{RunControl, StaticParams, StaticReport, prepare_strip};

/// The static stage of `params`: strip prepared (mesh read, FEM condensed), then analysed.
fn run(params: &StaticParams) -> static_contact::Result<StaticReport> {
    let strip = prepare_strip(params)?;
    strip.analyse(params, &params.post_springs()?, &RunControl::none())
}

/// `params` after meshing ahead (gmsh) or finding the mesh in the cache, so that the timed runs
/// read it from the cache (a Tet10 strip is the cached Tet4 file raised to Tet10 on reading).
fn with_cached_mesh(params: StaticParams) -> StaticParams {
    resolve_mesh(&params).expect("mesh for the benchmark (gmsh installed?)");
    params
}

fn default_eta(c: &mut Criterion) {
    let default = with_cached_mesh(StaticParams::default());
    let reference = with_cached_mesh(StaticParams {
        strip_posts: Some(10),
        ..StaticParams::default()
    });
    let mut group = c.benchmark_group("static_contact");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(1))
        .measurement_time(Duration::from_secs(1));
    group.bench_function("eta_10_post_strip_tet10", |b| {
        b.iter(|| {
            run(&reference)
                .expect("10-post strip")
                .effective_contact_ratio
        })
    });
    let scratch = tempfile::tempdir().expect("a scratch directory for the meshes");
    let setnumbers = strip_mesh_parameters(&StaticParams::default());
    let mut generation = 0;
    group.bench_function("gmsh_default_strip_tet10", |b| {
        b.iter(|| {
            generation += 1;
            let out = scratch.path().join(format!("strip-{generation}.msh"));
            generate_mesh("slider-strip", &out, &setnumbers)
                .expect("gmsh meshes the default strip");
            std::fs::remove_file(&out).expect("remove the scratch mesh");
        })
    });
    group.bench_function("eta_default_scene_100x100_tet10", |b| {
        b.iter(|| {
            run(&default)
                .expect("default scene")
                .effective_contact_ratio
        })
    });
    group.finish();
}

criterion_group!(benches, default_eta);
criterion_main!(benches);
