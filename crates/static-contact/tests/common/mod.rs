//! Shared inputs of the static-contact integration tests.

use static_contact::params::{MeshSizes, StaticParams};
use static_contact::{RunControl, StaticAnalysis, prepare_strip};

/// The tests' small strip: 10 posts, Tet4, tip-disk edges of a/4 (the committed
/// `slider-strip_p40um_d20um_n10_tet4_10k.msh` is this strip); everything else the defaults.
pub fn ten_post_tet4() -> StaticParams {
    StaticParams {
        strip_posts: Some(10),
        element_order: 1,
        mesh_sizes: MeshSizes {
            h_post_over_radius: 0.25,
            ..MeshSizes::default()
        },
        ..StaticParams::default()
    }
}

/// The whole static run of `params`: the strip prepared, then analysed (never stopped).
#[allow(dead_code)] // not every test file runs the whole stage
pub fn run(params: &StaticParams) -> static_contact::Result<StaticAnalysis> {
    let strip = prepare_strip(params)?;
    let report = strip.analyse(params, &params.post_springs()?, &RunControl::none())?;
    Ok(strip.into_analysis(params, report))
}
