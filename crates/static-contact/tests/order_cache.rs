//! The fill-reducing ordering stored in a mesh cache (`static_contact::order_cache`): a second
//! build of the same strip reads it instead of running METIS and condenses to the same
//! compliance.

mod common;

use static_contact::scene::StripModel;

#[test]
fn a_second_build_reuses_the_stored_ordering_and_gives_the_same_compliance() {
    let params = common::ten_post_tet4();
    let mesh_file = static_contact::mesh_source::workspace_root()
        .join("meshes/slider-strip_p40um_d20um_n10_tet4_10k.msh");
    let cache = tempfile::tempdir().expect("temporary cache folder");
    let build = || {
        let mesh = gmsh_mesh::read_msh(&mesh_file).expect("committed 10-post strip");
        StripModel::build_with_order_cache(mesh, params.strip_config(), Some(cache.path()))
            .expect("strip FEM")
    };
    let first = build();
    let second = build();
    assert!(
        !first.slider.stats.ordering_cached && second.slider.stats.ordering_cached,
        "the first build stores the ordering (cached: {}), the second reads it (cached: {})",
        first.slider.stats.ordering_cached,
        second.slider.stats.ordering_cached
    );
    let stored = std::fs::read_dir(cache.path())
        .expect("cache folder")
        .count();
    assert_eq!(stored, 1, "one ordering file for the slider");
    let (a, b) = (
        &first.slider.compliance_m_per_n,
        &second.slider.compliance_m_per_n,
    );
    let worst = (a - b).abs().max() / a.abs().max();
    assert!(
        worst < 1e-12,
        "post-tip compliance (m/N) with the stored ordering differs by {worst:e} relative"
    );
}
