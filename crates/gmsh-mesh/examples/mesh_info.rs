//! Print the summary of an MSH 4.1 file: `cargo run -p gmsh-mesh --example mesh_info -- FILE [--json]`.

fn main() -> std::process::ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.iter().find(|a| !a.starts_with("--")) else {
        eprintln!("usage: mesh_info FILE.msh [--json]");
        return std::process::ExitCode::from(2);
    };
    match gmsh_mesh::mesh_info(path) {
        Ok(info) if args.iter().any(|a| a == "--json") => match serde_json::to_string_pretty(&info)
        {
            Ok(json) => {
                println!("{json}");
                std::process::ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                std::process::ExitCode::FAILURE
            }
        },
        Ok(info) => {
            print!("{info}");
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
