//! `sawdrive mesh info FILE`.

use gmsh_mesh::mesh_info;

use crate::cli::MeshInfoArgs;

pub fn info(args: &MeshInfoArgs) -> anyhow::Result<()> {
    let info = mesh_info(&args.file)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print!("{info}");
    }
    Ok(())
}
