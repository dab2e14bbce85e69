//! Matrix-free or assembled, on the punch meshes: one-thread times of one product y = K x with
//! the assembled full-row CSR (f64 values, CG's product; f32 values, the smoothers' products) and
//! with elastic-fem's matrix-free operator (`matrix_free`, both ways of holding the geometry), and
//! the set-up each needs. One JSON object per mesh on stdout; the numbers and the choice are in
//! crates/elastic-fem/README.md, "Matrix-free or assembled".
//!
//! ```sh
//! cargo run --release -p validation --example punch_operator -- --level 3 [--products 40]
//! cargo run --release -p validation --example punch_operator -- MESH.msh
//! ```
//! Products: the median of `--products` repetitions (default 40) after one warm-up. Set-up:
//! `assembled` = pattern + assembly + full-row CSR + f32 copy; `matrix_free_*` = the operator's
//! element data (`jacobians` is refused on a mesh with curved elements, reported as null).

use std::time::Instant;

use contact_springs::Material;
use elastic_fem::matrix_free::{MatrixFreeGeometry, MatrixFreeStiffness};
use elastic_fem::sparse::CsrMatrix;
use elastic_fem::{Model, StiffnessPattern, assemble_stiffness};
use validation::punch::fem_material;
use validation::{PunchMesh, benchmark_punch_mesh};

fn median_s(repetitions: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut t: Vec<f64> = (0..repetitions)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let s = Instant::now();
    let v = f();
    (v, s.elapsed().as_secs_f64())
}

fn measure(
    path: &std::path::Path,
    products: usize,
) -> Result<serde_json::Value, Box<dyn std::error::Error>> {
    let mesh = PunchMesh::read(path)?;
    let material = fem_material(&Material::lithium_niobate())?;
    let model = Model::new(mesh.nodes.clone(), mesh.connectivity.clone(), material)?;
    let model = &model;
    let (pattern, pattern_s) = timed(|| StiffnessPattern::build(model));
    let (stiffness, assembly_s) = timed(|| assemble_stiffness(model, &pattern));
    let stiffness = stiffness?;
    drop(pattern);
    let (csr, csr_s) = timed(|| CsrMatrix::from_symmetric(&stiffness));
    let csr = csr?;
    drop(stiffness);
    let (single, single_s) = timed(|| csr.single_precision());
    let dim = model.dof_count();
    let x: Vec<f64> = (0..dim)
        .map(|i| ((i * 7919) % 1000) as f64 * 1e-12)
        .collect();
    let mut y = vec![0.0; dim];
    let mut reference = vec![0.0; dim];
    csr.mul_vec(&x, &mut reference);
    let csr_f64_s = median_s(products, || csr.mul_vec(&x, &mut y));
    let csr_f32_s = median_s(products, || csr.mul_vec_single(&single, &x, &mut y));
    let mut free = serde_json::Map::new();
    for (name, geometry) in [
        ("gradients", MatrixFreeGeometry::Gradients),
        ("jacobians", MatrixFreeGeometry::Jacobians),
    ] {
        let (operator, setup_s) = timed(|| MatrixFreeStiffness::new(model, geometry));
        let value = match operator {
            Ok(op) => {
                let product_s = median_s(products, || op.mul_vec(&x, &mut y));
                let scale = reference.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let diff = y
                    .iter()
                    .zip(&reference)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                serde_json::json!({
                    "setup_s": setup_s, "product_s": product_s,
                    "memory_mb": op.memory_bytes() as f64 / 1e6,
                    "max_relative_difference_to_csr": diff / scale,
                })
            }
            Err(e) => serde_json::json!({ "refused": e.to_string() }),
        };
        free.insert(name.into(), value);
    }
    Ok(serde_json::json!({
        "mesh": path.display().to_string(),
        "unknowns": dim,
        "elements": model.element_count(),
        "curved_elements": model.quality().curved_elements,
        "csr_entries": csr.nnz(),
        "assembled": {
            "pattern_s": pattern_s, "assembly_s": assembly_s, "full_rows_s": csr_s, "f32_copy_s": single_s,
            "memory_mb": (csr.memory_bytes() + 4 * csr.nnz()) as f64 / 1e6,
            "product_f64_s": csr_f64_s, "product_f32_s": csr_f32_s,
        },
        "matrix_free": free,
        "products_timed": products,
    }))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut paths = Vec::new();
    let mut products = 40;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--products" {
            products = args.next().ok_or("--products needs a number")?.parse()?;
            if products == 0 {
                return Err("--products must be at least 1".into());
            }
        } else if arg == "--level" {
            let level = args.next().ok_or("--level needs a number")?;
            paths.push(benchmark_punch_mesh(&level)?);
        } else {
            paths.push(std::path::PathBuf::from(arg));
        }
    }
    if paths.is_empty() {
        return Err("usage: punch_operator [--products N] (--level L | MESH.msh) ...".into());
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    for path in paths {
        let line = pool.install(|| measure(&path, products).map_err(|e| e.to_string()))?;
        println!("{line}");
    }
    Ok(())
}
