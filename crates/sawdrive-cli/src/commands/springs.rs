//! `sawdrive springs`: the Johnson springs of one post.

use anyhow::{Context, anyhow};
use contact_springs::{Material, post_springs};
use sawdrive::units::{Dimension, format_quantity, parse_quantity};

use crate::cli::SpringsArgs;

fn named_material(flag: &str, name: &str) -> anyhow::Result<Material> {
    Material::named(name)
        .ok_or_else(|| anyhow!("--{flag} {name}: unknown material, use si or linbo3"))
}

pub fn run(args: &SpringsArgs) -> anyhow::Result<()> {
    let diameter_m = parse_quantity(&args.diameter, Dimension::Length).context("--diameter")?;
    if diameter_m <= 0.0 {
        return Err(anyhow!("--diameter {}: must be > 0", args.diameter));
    }
    let slider = named_material("slider", &args.slider)?;
    let stator = named_material("stator", &args.stator)?;
    let springs = post_springs(&slider, &stator, 0.5 * diameter_m).context("--diameter")?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&springs)?);
        return Ok(());
    }
    let modulus = |m: &Material| {
        format!(
            "G = {}, ν = {}",
            format_quantity(m.shear_modulus_pa, Dimension::Pressure),
            m.poisson_ratio
        )
    };
    println!(
        "Johnson springs of one rigid post, d = {} (a = {})",
        format_quantity(diameter_m, Dimension::Length),
        format_quantity(0.5 * diameter_m, Dimension::Length)
    );
    println!(
        "slider {} ({}), stator {} ({})\n",
        slider.name,
        modulus(&slider),
        stator.name,
        modulus(&stator)
    );
    println!(
        "{:<6} {:<44} {:>14}",
        "spring", "boundary condition on the post disk", "N/m"
    );
    let rows = [
        ("k_pn", "slider, bonded normal", springs.k_pn_n_per_m),
        ("k_pt", "slider, bonded tangential", springs.k_pt_n_per_m),
        ("k_sn", "stator, frictionless normal", springs.k_sn_n_per_m),
        (
            "k_st",
            "stator, tangential with u_z free",
            springs.k_st_n_per_m,
        ),
        (
            "k_n",
            "normal in series (1/k_pn + 1/k_sn)^-1",
            springs.k_n_n_per_m,
        ),
        (
            "k_t",
            "tangential in series (1/k_pt + 1/k_st)^-1",
            springs.k_t_n_per_m,
        ),
    ];
    for (name, condition, k) in rows {
        println!("{name:<6} {condition:<44} {k:>14.6e}");
    }
    Ok(())
}
