//! The committed meshes in meshes/ read back with the contract's groups and the right geometry.
//!
//! Which checks are exact and which are discretisation-bounded:
//! - Polyhedral parts (the slider-body box, the stator block, flat faces such as `stator_top`,
//!   `slider_sym_y0`) are tiled exactly by straight tets/triangles: volume and area agree with the
//!   analytic value to round-off, checked at 1e-9 relative.
//! - Curved parts (punch rim r = a, hemisphere r = R, post cylinders) are approximated. Tet4 /
//!   Tri3 meshes have their boundary nodes on the true surface, so they are *inscribed*: a disk of
//!   radius a cut into chords of angle θ_i loses Σ a²/2 (θ_i − sin θ_i) ≤ (area)(1 − sin θ/θ)
//!   with θ the largest chord angle measured on the mesh; a sphere of radius R tiled by flat
//!   triangles of circumradius ρ loses at most Σ A_i (R − √(R² − ρ_i²)) (R/(R − g_max))².
//!   The tests assert the error has the right sign and lies within those bounds.
//! - Tet10 / Tri6 meshes put midside nodes on the curved surfaces: their error must be at least
//!   ten times below the straight-sided (Tet4) bound of the same corner mesh — if gmsh left the
//!   midside nodes at the straight midpoints, the error would equal the Tet4 error and fail.

mod common;

use std::collections::HashSet;
use std::f64::consts::PI;

use common::{committed_mesh, inward_face_count, relative_error};
use gmsh_mesh::geometry::{Point, triangle_area};
use gmsh_mesh::{Faces, TetMesh, read_msh};

/// Relative tolerance for volumes and areas of polyhedral (flat-faced) domains: round-off only.
const POLYHEDRAL_RTOL: f64 = 1e-9;
/// A Tet10 curved-boundary error must be this many times below the Tet4 chord bound.
const QUADRATIC_GAIN: f64 = 10.0;
/// Relative tolerance for a node to lie on a circle or sphere (gmsh places them to ~1e-12).
const ON_SURFACE_RTOL: f64 = 1e-9;

const PUNCH_RADIUS_M: f64 = 10e-6;

fn radius_xy(p: Point) -> f64 {
    (p[0] * p[0] + p[1] * p[1]).sqrt()
}

fn radius_xyz(p: Point) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

/// Largest chord angle 2 asin(c / 2r) among triangle edges of `group` whose both ends lie on a
/// circle of radius `r`; `offset` gives a point's (x, y) offset from its circle's centre.
fn largest_rim_chord_angle(
    mesh: &TetMesh,
    group: &str,
    r: f64,
    offset: impl Fn(Point) -> (f64, f64),
) -> f64 {
    let faces = mesh.group_faces(group).expect("group");
    let on_rim = |p: Point| {
        let (dx, dy) = offset(p);
        ((dx * dx + dy * dy).sqrt() - r).abs() < ON_SURFACE_RTOL * r
    };
    let mut largest: f64 = 0.0;
    for i in 0..faces.len() {
        let c = faces.corners(i);
        for (a, b) in [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])] {
            let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
            if on_rim(pa) && on_rim(pb) {
                let chord =
                    ((pa[0] - pb[0]).powi(2) + (pa[1] - pb[1]).powi(2) + (pa[2] - pb[2]).powi(2))
                        .sqrt();
                largest = largest.max(2.0 * (chord / (2.0 * r)).min(1.0).asin());
            }
        }
    }
    assert!(largest > 0.0, "found rim edges of {group} on r = {r}");
    largest
}

/// Upper bound of the relative area lost by a disk cut into chords of angle ≤ θ.
fn chord_area_bound(theta: f64) -> f64 {
    1.0 - theta.sin() / theta
}

/// Upper bound of the volume lost by tiling the sphere part (`far_field`) with flat triangles.
fn sphere_faceting_volume_bound(mesh: &TetMesh, radius: f64) -> f64 {
    let faces = mesh.group_faces("far_field").expect("far_field");
    let mut bound = 0.0;
    let mut largest_gap: f64 = 0.0;
    for i in 0..faces.len() {
        let p = faces.corners(i).map(|n| mesh.nodes[n]);
        let area = triangle_area(p);
        let edge = |a: Point, b: Point| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        let circumradius = edge(p[0], p[1]) * edge(p[1], p[2]) * edge(p[2], p[0]) / (4.0 * area);
        let gap = radius - (radius * radius - circumradius.min(radius).powi(2)).sqrt();
        largest_gap = largest_gap.max(gap);
        bound += area * gap;
    }
    bound * (radius / (radius - largest_gap)).powi(2)
}

fn names(mesh: &TetMesh) -> HashSet<String> {
    mesh.groups.iter().map(|g| g.name.clone()).collect()
}

fn expect_groups(mesh: &TetMesh, expected: &[&str]) {
    let expected: HashSet<String> = expected.iter().map(|s| s.to_string()).collect();
    assert_eq!(
        names(mesh),
        expected,
        "physical group names of {}",
        mesh.source
    );
}

#[test]
fn punch_tet4_full_model_has_contract_groups_and_inscribed_geometry() {
    let mesh = read_msh(committed_mesh("punch_a10um_R20a_tet4_5k.msh")).expect("punch mesh reads");
    expect_groups(&mesh, &["body", "punch", "free_surface", "far_field"]);
    let (a, big_r) = (PUNCH_RADIUS_M, 20.0 * PUNCH_RADIUS_M);
    for name in ["punch", "free_surface", "far_field"] {
        assert_eq!(
            inward_face_count(&mesh, name),
            0,
            "inward triangles of {name}"
        );
    }
    for n in mesh.group_nodes("punch").unwrap() {
        let p = mesh.nodes[n];
        assert!(
            p[2] == 0.0 && radius_xy(p) <= a * (1.0 + ON_SURFACE_RTOL),
            "punch node {p:?} on the disk"
        );
    }
    for n in mesh.group_nodes("far_field").unwrap() {
        assert!(
            relative_error(radius_xyz(mesh.nodes[n]), big_r) < ON_SURFACE_RTOL,
            "far-field node on r = R"
        );
    }
    let disk = PI * a * a;
    let area = mesh.face_area("punch").unwrap();
    let theta = largest_rim_chord_angle(&mesh, "punch", a, |p| (p[0], p[1]));
    let deficit = (disk - area) / disk;
    assert!(
        deficit > 0.0 && deficit <= chord_area_bound(theta),
        "punch area deficit {deficit:.3e} vs bound {:.3e}",
        chord_area_bound(theta)
    );
    let exact_volume = 2.0 / 3.0 * PI * big_r.powi(3);
    let volume_deficit = exact_volume - mesh.volume();
    let bound = sphere_faceting_volume_bound(&mesh, big_r);
    println!(
        "punch Tet4: area deficit {deficit:.3e} (bound {:.3e}), volume deficit {:.3e} (bound {:.3e})",
        chord_area_bound(theta),
        volume_deficit / exact_volume,
        bound / exact_volume
    );
    assert!(
        volume_deficit > 0.0 && volume_deficit <= bound,
        "hemisphere volume deficit {volume_deficit:.3e} vs bound {bound:.3e}"
    );
}

/// Tet10 quarter/half punch: midside nodes on the sphere and the rim; errors far below Tet4's.
fn check_quadratic_punch(file: &str, fraction: f64, sym_groups: &[&str]) {
    let mesh = read_msh(committed_mesh(file)).expect("punch mesh reads");
    let mut expected = vec!["body", "punch", "free_surface", "far_field"];
    expected.extend_from_slice(sym_groups);
    expect_groups(&mesh, &expected);
    assert_eq!(mesh.tets.order(), 2, "Tet10 mesh");
    let (a, big_r) = (PUNCH_RADIUS_M, 100.0 * PUNCH_RADIUS_M);
    for name in &expected[1..] {
        assert_eq!(
            inward_face_count(&mesh, name),
            0,
            "inward triangles of {name}"
        );
    }
    let Faces::Quadratic(far) = mesh.group_faces("far_field").unwrap() else {
        panic!("Tri6 far field")
    };
    for f in far {
        for &n in &f[3..] {
            assert!(
                relative_error(radius_xyz(mesh.nodes[n]), big_r) < ON_SURFACE_RTOL,
                "far-field midside node on the sphere"
            );
        }
    }
    let exact_volume = fraction * 2.0 / 3.0 * PI * big_r.powi(3);
    let tet4_bound = sphere_faceting_volume_bound(&mesh, big_r);
    let error = (mesh.volume() - exact_volume).abs();
    assert!(
        error * QUADRATIC_GAIN <= tet4_bound,
        "Tet10 volume error {error:.3e} vs Tet4 chord bound {tet4_bound:.3e}"
    );
    let disk = fraction * PI * a * a;
    let theta = largest_rim_chord_angle(&mesh, "punch", a, |p| (p[0], p[1]));
    let area_error = relative_error(mesh.face_area("punch").unwrap(), disk);
    println!(
        "{file}: volume error {:.3e} (Tet4 bound {:.3e}), area error {area_error:.3e} (Tet4 bound {:.3e})",
        error / exact_volume,
        tet4_bound / exact_volume,
        chord_area_bound(theta)
    );
    assert!(
        area_error * QUADRATIC_GAIN <= chord_area_bound(theta),
        "Tet10 punch area error {area_error:.3e} vs Tet4 bound {:.3e}",
        chord_area_bound(theta)
    );
    for name in sym_groups {
        for n in mesh.group_nodes(name).unwrap() {
            let p = mesh.nodes[n];
            let coordinate = if *name == "sym_x0" { p[0] } else { p[1] };
            assert!(
                coordinate.abs() < ON_SURFACE_RTOL * big_r,
                "{name} node {p:?} on its plane"
            );
        }
    }
}

#[test]
fn punch_tet10_quarter_model_places_midside_nodes_on_curved_boundaries() {
    check_quadratic_punch(
        "punch-quarter_a10um_R100a_tet10_8k.msh",
        0.25,
        &["sym_x0", "sym_y0"],
    );
}

#[test]
fn punch_tet10_half_model_places_midside_nodes_on_curved_boundaries() {
    check_quadratic_punch("punch-half_a10um_R100a_tet10_14k.msh", 0.5, &["sym_y0"]);
}

const PITCH_M: f64 = 40e-6;
const POST_RADIUS_M: f64 = 10e-6;
const POST_HEIGHT_M: f64 = 2e-6;
const BODY_THICKNESS_M: f64 = 0.5e-3;
const STATOR_DEPTH_M: f64 = 1e-3;

const STRIP_GROUPS: [&str; 14] = [
    "slider",
    "stator",
    "post_tips",
    "slider_top",
    "slider_sym_y0",
    "slider_sym_y1",
    "slider_x0",
    "slider_x1",
    "stator_top",
    "stator_bottom",
    "stator_sym_y0",
    "stator_sym_y1",
    "stator_x0",
    "stator_x1",
];

fn check_strip(mesh: &TetMesh, n_posts: usize) {
    expect_groups(mesh, &STRIP_GROUPS);
    let length = n_posts as f64 * PITCH_M;
    for name in &STRIP_GROUPS[2..] {
        assert_eq!(
            inward_face_count(mesh, name),
            0,
            "inward triangles of {name}"
        );
    }
    // Polyhedral: the stator block and the flat faces.
    let stator: f64 = mesh
        .group_tets("stator")
        .unwrap()
        .iter()
        .map(|&t| mesh.tet_volume(t))
        .sum();
    assert!(
        relative_error(stator, length * PITCH_M * STATOR_DEPTH_M) < POLYHEDRAL_RTOL,
        "stator volume {stator:e}"
    );
    let flat = [
        ("stator_top", length * PITCH_M),
        ("slider_top", length * PITCH_M),
        ("slider_sym_y0", length * BODY_THICKNESS_M),
        ("stator_sym_y1", length * STATOR_DEPTH_M),
        ("slider_x1", PITCH_M * BODY_THICKNESS_M),
    ];
    for (name, exact) in flat {
        assert!(
            relative_error(mesh.face_area(name).unwrap(), exact) < POLYHEDRAL_RTOL,
            "area of {name}"
        );
    }
    // Curved: post tips are inscribed polygons.
    let disks = n_posts as f64 * PI * POST_RADIUS_M * POST_RADIUS_M;
    let theta = largest_rim_chord_angle(mesh, "post_tips", POST_RADIUS_M, |p| {
        let cell = (p[0] / PITCH_M).floor();
        (p[0] - (cell + 0.5) * PITCH_M, p[1] - 0.5 * PITCH_M)
    });
    let deficit = (disks - mesh.face_area("post_tips").unwrap()) / disks;
    assert!(
        deficit > 0.0 && deficit <= chord_area_bound(theta),
        "post tip area deficit {deficit:.3e}"
    );
    // Slider = box + posts; the posts' error is bounded by their lateral area times the sagitta
    // r (1 − cos θ/2) of the largest rim chord, with a safety factor 2 on θ because the lateral
    // triangles are not a group whose chords we can measure.
    let slider: f64 = mesh
        .group_tets("slider")
        .unwrap()
        .iter()
        .map(|&t| mesh.tet_volume(t))
        .sum();
    let posts = n_posts as f64 * PI * POST_RADIUS_M * POST_RADIUS_M * POST_HEIGHT_M;
    let exact = length * PITCH_M * BODY_THICKNESS_M + posts;
    let sagitta = POST_RADIUS_M * (1.0 - theta.cos());
    let bound = n_posts as f64 * 2.0 * PI * POST_RADIUS_M * POST_HEIGHT_M * sagitta;
    println!(
        "strip n={n_posts}: tip area deficit {deficit:.3e} (bound {:.3e}), slider volume error {:.3e} (bound {:.3e})",
        chord_area_bound(theta),
        (slider - exact) / exact,
        bound / exact
    );
    assert!(
        (slider - exact).abs() <= bound,
        "slider volume error {:.3e} vs bound {bound:.3e}",
        slider - exact
    );
    // Separate bodies: no shared node.
    let slider_nodes: HashSet<usize> = mesh.group_nodes("slider").unwrap().into_iter().collect();
    assert!(
        mesh.group_nodes("stator")
            .unwrap()
            .iter()
            .all(|n| !slider_nodes.contains(n)),
        "slider and stator share no node"
    );
    for n in mesh.group_nodes("post_tips").unwrap() {
        assert!(mesh.nodes[n][2] == 0.0, "post tip node at z = 0");
    }
}

#[test]
fn slider_strip_has_contract_groups_exact_flat_parts_and_separate_bodies() {
    let mesh =
        read_msh(committed_mesh("slider-strip_p40um_d20um_n10_tet4_10k.msh")).expect("strip reads");
    assert!(!mesh.binary, "committed strip is ASCII");
    check_strip(&mesh, 10);
    assert!(
        mesh.periodic_node_pairs.is_empty(),
        "no periodic pairs without periodic_x"
    );
}

#[test]
fn periodic_slider_strip_pairs_every_x1_node_with_its_x0_image() {
    let mesh = read_msh(committed_mesh(
        "slider-strip-periodic_p40um_d20um_n1_tet4_1k.msh",
    ))
    .expect("strip reads");
    check_strip(&mesh, 1);
    let length = PITCH_M;
    for [slave, master] in &mesh.periodic_node_pairs {
        let (s, m) = (mesh.nodes[*slave], mesh.nodes[*master]);
        let shift = [s[0] - m[0], s[1] - m[1], s[2] - m[2]];
        assert!(
            (shift[0] - length).abs() < 1e-9 * length
                && shift[1].abs() < 1e-9 * length
                && shift[2].abs() < 1e-9 * length,
            "periodic pair offset {shift:?} equals (L, 0, 0)"
        );
    }
    let slaves: HashSet<usize> = mesh.periodic_node_pairs.iter().map(|p| p[0]).collect();
    for name in ["slider_x1", "stator_x1"] {
        for n in mesh.group_nodes(name).unwrap() {
            assert!(
                slaves.contains(&n),
                "node {n} of {name} has a periodic master"
            );
        }
    }
}

#[test]
fn slider_body_box_volume_is_exact_for_tet10() {
    let mesh = read_msh(committed_mesh("slider-body_5x5x0.5mm_tet10_2k.msh")).expect("body reads");
    expect_groups(&mesh, &["slider", "bottom", "top", "x0", "x1", "y0", "y1"]);
    assert!(
        relative_error(mesh.volume(), 5e-3 * 5e-3 * 0.5e-3) < POLYHEDRAL_RTOL,
        "slider body volume"
    );
    assert!(
        relative_error(mesh.face_area("bottom").unwrap(), 25e-6) < POLYHEDRAL_RTOL,
        "bottom area"
    );
    for name in ["bottom", "top", "x0", "x1", "y0", "y1"] {
        assert_eq!(
            inward_face_count(&mesh, name),
            0,
            "inward triangles of {name}"
        );
    }
}

/// Every committed mesh is ASCII MSH 4.1 text (printable ASCII, newlines and tabs only), so
/// `git grep` reads it as text; the binary gmsh output is converted exactly by
/// `scripts/msh-to-ascii.py` (meshes/README.md).
#[test]
fn every_committed_mesh_is_ascii_text() {
    let folder = committed_mesh("");
    let mut names: Vec<_> = std::fs::read_dir(&folder)
        .expect("meshes/ lists")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "msh"))
        .collect();
    names.sort();
    assert!(names.len() >= 6, "committed meshes found: {names:?}");
    for path in names {
        let bytes = std::fs::read(&path).expect("mesh reads");
        let stray = bytes
            .iter()
            .position(|&b| !(b == b'\n' || b == b'\t' || (0x20..0x7f).contains(&b)));
        assert_eq!(
            stray,
            None,
            "{}: a byte that is not ASCII text",
            path.display()
        );
        let mesh = read_msh(&path).expect("mesh reads");
        assert!(!mesh.binary, "{} is ASCII MSH", path.display());
    }
}
