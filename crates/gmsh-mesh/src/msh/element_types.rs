//! gmsh element type numbers (gmsh reference manual, "MSH file format", element types).

/// 3-node triangle.
pub const TRI3: i32 = 2;
/// 4-node tetrahedron.
pub const TET4: i32 = 4;
/// 6-node second-order triangle.
pub const TRI6: i32 = 9;
/// 10-node second-order tetrahedron.
pub const TET10: i32 = 11;

/// Number of nodes of a gmsh element type, for the types gmsh writes up to order 5
/// (simplices), order 4 (hexahedra) and the usual lower-order prisms and pyramids.
pub fn nodes_per_element(element_type: i32) -> Option<usize> {
    Some(match element_type {
        1 => 2,    // 2-node line
        2 => 3,    // 3-node triangle
        3 => 4,    // 4-node quadrangle
        4 => 4,    // 4-node tetrahedron
        5 => 8,    // 8-node hexahedron
        6 => 6,    // 6-node prism
        7 => 5,    // 5-node pyramid
        8 => 3,    // 3-node line
        9 => 6,    // 6-node triangle
        10 => 9,   // 9-node quadrangle
        11 => 10,  // 10-node tetrahedron
        12 => 27,  // 27-node hexahedron
        13 => 18,  // 18-node prism
        14 => 14,  // 14-node pyramid
        15 => 1,   // point
        16 => 8,   // 8-node quadrangle
        17 => 20,  // 20-node hexahedron
        18 => 15,  // 15-node prism
        19 => 13,  // 13-node pyramid
        20 => 9,   // 9-node incomplete triangle
        21 => 10,  // 10-node triangle
        22 => 12,  // 12-node incomplete triangle
        23 => 15,  // 15-node triangle
        24 => 15,  // 15-node incomplete triangle
        25 => 21,  // 21-node triangle
        26 => 4,   // 4-node line
        27 => 5,   // 5-node line
        28 => 6,   // 6-node line
        29 => 20,  // 20-node tetrahedron
        30 => 35,  // 35-node tetrahedron
        31 => 56,  // 56-node tetrahedron
        92 => 64,  // 64-node hexahedron
        93 => 125, // 125-node hexahedron
        _ => return None,
    })
}

/// Human-readable name of a gmsh element type, for notes.
pub fn element_type_name(element_type: i32) -> String {
    match element_type {
        1 => "2-node line".into(),
        8 => "3-node line".into(),
        15 => "point".into(),
        3 | 10 | 16 => "quadrangle".into(),
        5 | 12 | 17 | 92 | 93 => "hexahedron".into(),
        6 | 13 | 18 => "prism".into(),
        7 | 14 | 19 => "pyramid".into(),
        20..=25 => "higher-order triangle".into(),
        26..=28 => "higher-order line".into(),
        29..=31 => "higher-order tetrahedron".into(),
        other => format!("element type {other}"),
    }
}
