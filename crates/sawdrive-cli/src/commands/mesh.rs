//! `sawdrive mesh info FILE`.

use std::io::Write;

use gmsh_mesh::mesh_info;

use crate::cli::MeshInfoArgs;

pub fn info(args: &MeshInfoArgs) -> anyhow::Result<()> {
    let info = mesh_info(&args.file)?;
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", serde_json::to_string_pretty(&info)?)?;
    } else {
        write!(out, "{info}")?;
    }
    out.flush()?;
    Ok(())
}
