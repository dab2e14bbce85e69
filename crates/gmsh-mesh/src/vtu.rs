//! ParaView XML UnstructuredGrid (`.vtu`, ASCII) writer for a [`TetMesh`] with point and cell
//! fields. Reference: VTK File Formats, "XML File Formats / UnstructuredGrid".
//!
//! Cells are VTK_TETRA (10) or VTK_QUADRATIC_TETRA (24). VTK orders the Tet10 midside nodes on
//! edges (0,1) (1,2) (2,0) (0,3) (1,3) (2,3); gmsh on (0,1) (1,2) (2,0) (3,0) (3,2) (3,1): the
//! last two are swapped ([`GMSH_TO_VTK_TET10`]). Two cell fields are always written:
//! `gmsh_element_tag` and `gmsh_physical_tag` (0 where the tet has no physical volume).

use std::io::Write;
use std::path::Path;

use crate::atomic::write_atomically;
use crate::error::{MeshError, Result};
use crate::mesh::{TetMesh, Tets};

/// VTK cell type of the 4-node tetrahedron.
pub const VTK_TETRA: u8 = 10;
/// VTK cell type of the 10-node tetrahedron.
pub const VTK_QUADRATIC_TETRA: u8 = 24;
/// `vtk[i] = gmsh[GMSH_TO_VTK_TET10[i]]`: gmsh nodes 8 (edge 3-2) and 9 (edge 3-1) swap places.
pub const GMSH_TO_VTK_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// Cell fields the writer adds itself; user fields may not use these names.
const RESERVED_CELL_FIELDS: [&str; 2] = ["gmsh_element_tag", "gmsh_physical_tag"];

/// Values of a field: one scalar or one 3-vector per point (or per cell).
#[derive(Debug, Clone, Copy)]
pub enum FieldValues<'a> {
    /// One value per point/cell.
    Scalar(&'a [f64]),
    /// One 3-vector per point/cell (e.g. displacement (m)).
    Vector(&'a [[f64; 3]]),
}

impl FieldValues<'_> {
    fn len(&self) -> usize {
        match self {
            FieldValues::Scalar(v) => v.len(),
            FieldValues::Vector(v) => v.len(),
        }
    }
}

/// A named field. Put the unit in the name, e.g. `displacement_m`, `pressure_pa`.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// The values.
    pub values: FieldValues<'a>,
}

/// Write `mesh` with `point_fields` (one entry per node) and `cell_fields` (one per tet) to
/// `path`, atomically (temporary file + rename).
pub fn write_vtu(
    path: &Path,
    mesh: &TetMesh,
    point_fields: &[Field<'_>],
    cell_fields: &[Field<'_>],
) -> Result<()> {
    let file = path.display().to_string();
    check_fields(&file, point_fields, mesh.nodes.len(), "point", &[])?;
    check_fields(
        &file,
        cell_fields,
        mesh.tets.len(),
        "cell",
        &RESERVED_CELL_FIELDS,
    )?;
    write_atomically(path, |w| write_document(w, mesh, point_fields, cell_fields))
}

fn check_fields(
    file: &str,
    fields: &[Field<'_>],
    expected: usize,
    kind: &str,
    reserved: &[&str],
) -> Result<()> {
    let error = |field: &str, detail: String| MeshError::Field {
        file: file.to_string(),
        field: field.to_string(),
        detail,
    };
    for (i, field) in fields.iter().enumerate() {
        if field.name.is_empty() {
            return Err(error(
                field.name,
                format!("{kind} field {i} has an empty name"),
            ));
        }
        if reserved.contains(&field.name) || fields[..i].iter().any(|f| f.name == field.name) {
            return Err(error(
                field.name,
                format!("{kind} field name is used twice or reserved ({reserved:?})"),
            ));
        }
        if field.values.len() != expected {
            return Err(error(
                field.name,
                format!(
                    "{kind} field has {} values, the mesh has {expected} {kind}s",
                    field.values.len()
                ),
            ));
        }
        let first_bad = match field.values {
            FieldValues::Scalar(v) => v.iter().position(|x| !x.is_finite()),
            FieldValues::Vector(v) => v.iter().position(|x| !x.iter().all(|c| c.is_finite())),
        };
        if let Some(index) = first_bad {
            return Err(error(
                field.name,
                format!("non-finite value at {kind} {index}"),
            ));
        }
    }
    Ok(())
}

fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&apos;")
}

fn write_field(w: &mut dyn Write, field: &Field<'_>) -> std::io::Result<()> {
    let name = xml_escape(field.name);
    match field.values {
        FieldValues::Scalar(values) => {
            writeln!(
                w,
                "        <DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
            )?;
            for v in values {
                writeln!(w, "          {v:e}")?;
            }
        }
        FieldValues::Vector(values) => {
            writeln!(
                w,
                "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"3\" format=\"ascii\">"
            )?;
            for v in values {
                writeln!(w, "          {:e} {:e} {:e}", v[0], v[1], v[2])?;
            }
        }
    }
    writeln!(w, "        </DataArray>")
}

/// `<CellData>`: the given cell fields, then each tetrahedron's gmsh element and physical tags.
fn write_cell_data(
    w: &mut dyn Write,
    mesh: &TetMesh,
    cell_fields: &[Field<'_>],
) -> std::io::Result<()> {
    writeln!(w, "      <CellData>")?;
    for field in cell_fields {
        write_field(w, field)?;
    }
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"gmsh_element_tag\" format=\"ascii\">"
    )?;
    for tag in &mesh.tet_tags {
        writeln!(w, "          {tag}")?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        "        <DataArray type=\"Int32\" Name=\"gmsh_physical_tag\" format=\"ascii\">"
    )?;
    for group in &mesh.tet_groups {
        writeln!(w, "          {}", group.unwrap_or(0))?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </CellData>")?;
    Ok(())
}

/// `<Cells>`: connectivity (Tet10 in VTK's node order), offsets and cell types.
fn write_cells(w: &mut dyn Write, mesh: &TetMesh) -> std::io::Result<()> {
    writeln!(w, "      <Cells>")?;
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    )?;
    match &mesh.tets {
        Tets::Linear(tets) => {
            for t in tets {
                writeln!(w, "          {} {} {} {}", t[0], t[1], t[2], t[3])?;
            }
        }
        Tets::Quadratic(tets) => {
            for t in tets {
                let vtk: Vec<String> = GMSH_TO_VTK_TET10
                    .iter()
                    .map(|&k| t[k].to_string())
                    .collect();
                writeln!(w, "          {}", vtk.join(" "))?;
            }
        }
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    )?;
    let per_cell = mesh.tets.nodes_per_tet();
    for i in 1..=mesh.tets.len() {
        writeln!(w, "          {}", i * per_cell)?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    )?;
    let cell_type = if mesh.tets.order() == 1 {
        VTK_TETRA
    } else {
        VTK_QUADRATIC_TETRA
    };
    for _ in 0..mesh.tets.len() {
        writeln!(w, "          {cell_type}")?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Cells>")?;
    Ok(())
}

fn write_document(
    w: &mut dyn Write,
    mesh: &TetMesh,
    point_fields: &[Field<'_>],
    cell_fields: &[Field<'_>],
) -> std::io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        mesh.nodes.len(),
        mesh.tets.len()
    )?;
    writeln!(w, "      <PointData>")?;
    for field in point_fields {
        write_field(w, field)?;
    }
    writeln!(w, "      </PointData>")?;
    write_cell_data(w, mesh, cell_fields)?;
    writeln!(w, "      <Points>")?;
    writeln!(
        w,
        "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">"
    )?;
    for p in &mesh.nodes {
        writeln!(w, "          {:e} {:e} {:e}", p[0], p[1], p[2])?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Points>")?;
    write_cells(w, mesh)?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}
