//! Solves all four springs on the given punch meshes (experiments).
use contact_springs::Material;
use validation::{AssembledPunch, PunchMesh, PunchSolveOptions, Spring};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for path in std::env::args().skip(1) {
        let t = std::time::Instant::now();
        let mesh = PunchMesh::read(path.as_ref())?;
        let read_s = t.elapsed().as_secs_f64();
        for material in [Material::silicon(), Material::lithium_niobate()]
            .into_iter()
            .filter(|m| std::env::var("PROBE_MATERIAL").map_or(true, |v| v == m.name))
        {
            let assembled = AssembledPunch::new(&mesh, &material)?;
            for spring in Spring::ALL
                .into_iter()
                .filter(|s| std::env::var("PROBE_SPRING").map_or(true, |v| v.contains(s.label())))
            {
                let r = assembled.solve(spring, &PunchSolveOptions::default())?;
                let k = spring.analytic_n_per_m(&material, mesh.radius_m)?;
                println!(
                    "{path} {} {} R/a {:.1} n {} k/kan {:.5} clamped {:.5} read {read_s:.2} nnzL {} num {:.2}s",
                    material.name,
                    spring,
                    mesh.truncation_ratio(),
                    r.unknowns,
                    r.stiffness_n_per_m / k,
                    r.clamped_stiffness_n_per_m / k,
                    r.factor_nnz,
                    r.timings.numeric_s
                );
            }
        }
    }
    Ok(())
}
