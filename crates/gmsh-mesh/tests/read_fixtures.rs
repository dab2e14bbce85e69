//! Reading small fixtures: sparse and out-of-order tags, skipped element types, orientation,
//! second-order node placement, and every error kind the CLI must report.

mod common;

use common::{fixture, inward_face_count, relative_error};
use gmsh_mesh::{
    BadElementPolicy, Faces, MeshError, MeshInfo, ReadOptions, Tets, parse_msh, read_msh,
    read_msh_with,
};

/// Volumes of polyhedral domains are sums of exact tet volumes: only round-off remains.
const POLYHEDRAL_VOLUME_RTOL: f64 = 1e-9;

#[test]
fn sparse_out_of_order_tags_map_to_the_right_coordinates() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture reads");
    assert_eq!(mesh.nodes.len(), 5, "node count (unused node 77 dropped)");
    assert_eq!(mesh.tet_tags, vec![12, 900], "tet tags in file order");
    let position = |tag: u64| {
        mesh.nodes[mesh
            .node_tags
            .iter()
            .position(|&t| t == tag)
            .expect("tag kept")]
    };
    assert_eq!(position(40), [0.0, 0.0, 0.0], "coordinates of node tag 40");
    assert_eq!(position(7), [1.0, 0.0, 0.0], "coordinates of node tag 7");
    assert_eq!(
        position(1000),
        [0.0, 1.0, 0.0],
        "coordinates of node tag 1000"
    );
    assert_eq!(position(23), [0.0, 0.0, 1.0], "coordinates of node tag 23");
    assert_eq!(position(5), [1.0, 1.0, 1.0], "coordinates of node tag 5");
    let Tets::Linear(tets) = &mesh.tets else {
        panic!("fixture is Tet4")
    };
    let tags: Vec<u64> = tets[1].iter().map(|&n| mesh.node_tags[n]).collect();
    assert_eq!(
        tags,
        vec![40, 7, 1000, 23],
        "connectivity of element 900 by node tag"
    );
    assert!(
        relative_error(mesh.volume(), 0.5) < POLYHEDRAL_VOLUME_RTOL,
        "volume {}",
        mesh.volume()
    );
}

#[test]
fn groups_are_found_by_name_and_tag_and_unnamed_groups_get_a_kind_name() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture reads");
    let body = mesh.group("body").expect("volume group body");
    assert_eq!(
        (body.dim, body.tag, body.named),
        (3, 1, true),
        "body group dim/tag"
    );
    let other = mesh.group("volume_2").expect("unnamed volume group");
    assert!(!other.named, "volume 2 has no $PhysicalNames entry");
    assert_eq!(
        mesh.group_tets("body").expect("body tets"),
        vec![1],
        "tets of body (element 900)"
    );
    assert_eq!(
        mesh.tet_groups,
        vec![Some(2), Some(1)],
        "physical tag per tet"
    );
    assert_eq!(
        mesh.group_faces("bottom face")
            .expect("name with a space")
            .len(),
        1,
        "bottom face triangles"
    );
    let nodes = mesh.group_nodes("slanted").expect("slanted nodes");
    let tags: Vec<u64> = nodes.iter().map(|&n| mesh.node_tags[n]).collect();
    assert_eq!(tags.len(), 3, "slanted node count");
    assert!(
        nodes.windows(2).all(|w| w[0] < w[1]),
        "group_nodes sorted and unique"
    );
    let mut sorted_tags = tags.clone();
    sorted_tags.sort_unstable();
    assert_eq!(sorted_tags, vec![5, 23, 1000], "slanted node tags");
    assert!(
        mesh.notes.iter().any(|n| n.contains("2-node line"))
            && mesh.notes.iter().any(|n| n.contains("point")),
        "skipped line and point elements noted: {:?}",
        mesh.notes
    );
    assert!(
        mesh.notes.iter().any(|n| n.contains("$Comments")),
        "skipped section noted"
    );
}

#[test]
fn boundary_triangles_are_reoriented_outward() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture reads");
    // The file lists the bottom triangle (40, 7, 1000) with its normal pointing into the body.
    let Faces::Linear(bottom) = mesh.group_faces("bottom face").expect("bottom") else {
        panic!("Tri3")
    };
    let tags: Vec<u64> = bottom[0].iter().map(|&n| mesh.node_tags[n]).collect();
    assert_eq!(
        tags,
        vec![40, 1000, 7],
        "bottom triangle flipped to point out of the body (-z)"
    );
    assert_eq!(
        inward_face_count(&mesh, "bottom face"),
        0,
        "inward bottom triangles"
    );
    assert_eq!(
        inward_face_count(&mesh, "slanted"),
        0,
        "inward slanted triangles"
    );
    assert!(
        mesh.notes.iter().any(|n| n.contains("interface")),
        "interface triangle noted: {:?}",
        mesh.notes
    );
}

#[test]
fn missing_group_error_names_the_group_and_lists_the_available_ones() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture reads");
    let message = mesh
        .group_faces("punch")
        .expect_err("no punch group")
        .to_string();
    assert!(
        message.contains("\"punch\""),
        "names the missing group: {message}"
    );
    assert!(
        message.contains("bottom face, slanted, interface"),
        "lists surface groups: {message}"
    );
    assert!(
        message.contains("sparse_tags_two_tets.msh"),
        "names the file: {message}"
    );
    assert!(
        mesh.group_tets("slanted").is_err(),
        "a surface group is not a volume group"
    );
}

#[test]
fn inverted_tet_is_an_error_by_default_naming_its_tag_and_reportable_on_request() {
    let error = read_msh(fixture("inverted_tet.msh")).expect_err("inverted tet rejected");
    let message = error.to_string();
    assert!(
        matches!(
            error,
            MeshError::BadElements {
                inverted_count: 1,
                ..
            }
        ),
        "error kind: {message}"
    );
    assert!(
        message.contains("inverted [2]"),
        "names element tag 2: {message}"
    );
    let options = ReadOptions {
        bad_elements: BadElementPolicy::Report,
    };
    let mesh = read_msh_with(fixture("inverted_tet.msh"), &options).expect("loads when reporting");
    let quality = mesh.quality();
    assert_eq!(
        quality.inverted_tags,
        vec![2],
        "inverted tet tags in the quality report"
    );
    assert!(
        mesh.notes.iter().any(|n| n.contains("inverted")),
        "note about inverted tets"
    );
}

#[test]
fn unsupported_version_error_says_which_version_is_read() {
    let message = read_msh(fixture("box_msh22.msh"))
        .expect_err("MSH 2.2 rejected")
        .to_string();
    assert!(
        message.contains("2.2") && message.contains("4.1"),
        "names found and supported versions: {message}"
    );
    let msh30 = b"$MeshFormat\n3.0 0 8\n$EndMeshFormat\n";
    let message = parse_msh(msh30, "v3.msh", &ReadOptions::default())
        .expect_err("3.0 rejected")
        .to_string();
    assert!(
        message.contains("3.0") && message.contains("v3.msh"),
        "names version 3.0 and file: {message}"
    );
}

#[test]
fn truncated_file_error_names_the_section_and_what_is_missing() {
    let bytes = std::fs::read(fixture("sparse_tags_two_tets.msh")).expect("fixture");
    let cut = String::from_utf8_lossy(&bytes)
        .find("$EndNodes")
        .expect("has $EndNodes");
    let message = parse_msh(&bytes[..cut], "cut.msh", &ReadOptions::default())
        .expect_err("truncated")
        .to_string();
    assert!(
        message.contains("truncated") && message.contains("$EndNodes"),
        "truncation message: {message}"
    );
    let in_block = String::from_utf8_lossy(&bytes)
        .find("0.5 0.5 0.5")
        .expect("last coordinate line");
    // Drop the last coordinate line: the node block is one node short.
    let mut damaged = bytes[..in_block].to_vec();
    damaged.extend_from_slice(&bytes[in_block + "0.5 0.5 0.5\n".len()..]);
    let message = parse_msh(&damaged, "short.msh", &ReadOptions::default())
        .expect_err("short block")
        .to_string();
    assert!(
        message.contains("section $Nodes")
            && message.contains("line")
            && message.contains("byte offset"),
        "locates the error: {message}"
    );
}

#[test]
fn wrong_section_order_is_reported() {
    let text =
        String::from_utf8(std::fs::read(fixture("sparse_tags_two_tets.msh")).expect("fixture"))
            .expect("utf8");
    let nodes = &text[text.find("$Nodes").unwrap()..text.find("$Elements").unwrap()];
    let elements = &text[text.find("$Elements").unwrap()..text.find("$Comments").unwrap()];
    let swapped = text
        .replacen(nodes, "@NODES@", 1)
        .replacen(elements, nodes, 1)
        .replacen("@NODES@", elements, 1);
    let error =
        parse_msh(swapped.as_bytes(), "swapped.msh", &ReadOptions::default()).expect_err("order");
    assert!(
        matches!(error, MeshError::SectionOrder { .. }),
        "section order error: {error}"
    );
    assert!(
        error.to_string().contains("$Nodes"),
        "names the misplaced section: {error}"
    );
}

#[test]
fn dangling_node_reference_names_element_and_node() {
    let text =
        String::from_utf8(std::fs::read(fixture("sparse_tags_two_tets.msh")).expect("fixture"))
            .expect("utf8");
    let damaged = text.replace("900 40 7 1000 23", "900 40 7 1000 24");
    let message = parse_msh(damaged.as_bytes(), "dangling.msh", &ReadOptions::default())
        .expect_err("bad")
        .to_string();
    assert!(
        message.contains("element 900") && message.contains("node tag 24"),
        "dangling reference: {message}"
    );
}

#[test]
fn missing_file_error_names_the_path() {
    let message = read_msh(fixture("does_not_exist.msh"))
        .expect_err("missing")
        .to_string();
    assert!(
        message.contains("does_not_exist.msh") && message.contains("reading"),
        "io error: {message}"
    );
}

#[test]
fn binary_and_ascii_copies_of_a_box_give_the_same_volume_and_groups() {
    let binary = read_msh(fixture("box_coarse_tet4_binary.msh")).expect("binary box");
    let tet10 = read_msh(fixture("box_coarse_tet10.msh")).expect("ascii Tet10 box");
    assert!(binary.binary && !tet10.binary, "encodings detected");
    let exact = 2e-3 * 1e-3 * 0.5e-3;
    for mesh in [&binary, &tet10] {
        assert!(
            relative_error(mesh.volume(), exact) < POLYHEDRAL_VOLUME_RTOL,
            "box volume {}",
            mesh.volume()
        );
        assert!(
            relative_error(mesh.face_area("bottom").unwrap(), 2e-6) < POLYHEDRAL_VOLUME_RTOL,
            "bottom area"
        );
        for name in ["bottom", "top", "x0", "x1", "y0", "y1"] {
            assert_eq!(
                inward_face_count(mesh, name),
                0,
                "inward triangles of {name}"
            );
        }
    }
    assert_eq!(tet10.tets.order(), 2, "Tet10 order");
    assert!(
        matches!(tet10.group_faces("top").unwrap(), Faces::Quadratic(_)),
        "Tri6 faces with Tet10"
    );
}

#[test]
fn gmsh_tet10_midside_nodes_follow_the_documented_order() {
    let mesh = read_msh(fixture("box_coarse_tet10.msh")).expect("Tet10 box");
    let Tets::Quadratic(tets) = &mesh.tets else {
        panic!("Tet10")
    };
    for t in tets {
        for (k, [i, j]) in gmsh_mesh::geometry::TET10_EDGES.iter().enumerate() {
            let (a, b, m) = (mesh.nodes[t[*i]], mesh.nodes[t[*j]], mesh.nodes[t[4 + k]]);
            for d in 0..3 {
                assert!(
                    (0.5 * (a[d] + b[d]) - m[d]).abs() < 1e-12,
                    "node {} is the midpoint of corners {i}-{j}",
                    4 + k
                );
            }
        }
    }
}

#[test]
fn mesh_info_serialises_and_displays_groups_and_quality() {
    let mesh = read_msh(fixture("sparse_tags_two_tets.msh")).expect("fixture reads");
    let info = MeshInfo::from_mesh(&mesh);
    assert_eq!(
        (info.node_count, info.tet_count),
        (5, 2),
        "counts in MeshInfo"
    );
    let text = info.to_string();
    assert!(
        text.contains("\"bottom face\"") && text.contains("radius ratio"),
        "display: {text}"
    );
    let json = serde_json::to_value(&info).expect("serialises");
    assert_eq!(
        json["groups"][1]["name"], "bottom face",
        "group name in JSON"
    );
    assert_eq!(json["bounding_box_max_m"][2], 1.0, "bounding box in JSON");
    let from_file = gmsh_mesh::mesh_info(fixture("inverted_tet.msh"));
    assert!(from_file.is_err(), "mesh_info refuses inverted tets");
}

#[test]
fn syntax_error_location_points_at_the_offending_line() {
    let text = String::from_utf8(std::fs::read(fixture("box_coarse_tet10.msh")).expect("fixture"))
        .expect("utf8");
    let nodes_start = text.find("$Nodes").expect("nodes");
    let bad_line_start = nodes_start
        + text[nodes_start..]
            .find("\n0 0 0.0005\n")
            .expect("a coordinate line")
        + 1;
    let damaged = format!(
        "{}0 0 abc\n{}",
        &text[..bad_line_start],
        &text[bad_line_start + "0 0 0.0005\n".len()..]
    );
    let expected_line = 1 + text[..bad_line_start].matches('\n').count();
    let error = parse_msh(damaged.as_bytes(), "abc.msh", &ReadOptions::default())
        .expect_err("bad coordinate");
    let MeshError::Syntax {
        at,
        expected,
        found,
        ..
    } = &error
    else {
        panic!("syntax error expected: {error}")
    };
    assert_eq!(
        at.line, expected_line,
        "line of the bad coordinate: {error}"
    );
    assert_eq!(at.section, "Nodes", "section of the bad coordinate");
    assert_eq!(
        &damaged.as_bytes()[at.byte_offset..at.byte_offset + 3],
        b"abc",
        "byte offset of the bad token"
    );
    assert!(
        expected.contains("z coordinate") && found.contains("abc"),
        "what was expected and found: {error}"
    );
}
