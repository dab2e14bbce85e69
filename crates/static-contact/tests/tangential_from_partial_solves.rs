//! The strip's tangential tip compliance and its normal–tangential cross block from partial
//! forward solves (elastic-fem `sparse_rhs`: the disk unknowns' elimination-tree paths only)
//! equal the ones from full solves with the same factor, on the committed 10-post Tet4 strip.

mod common;

use nalgebra::DMatrix;
use static_contact::prepare_strip;

fn relative_difference(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax()
}

#[test]
fn tangential_and_cross_compliances_from_partial_forward_solves_equal_those_from_full_solves() {
    let strip = prepare_strip(&common::ten_post_tet4()).expect("10-post strip");
    let slider = &strip.model.slider;
    let (partial, work) = slider
        .tangential_compliance_with_work()
        .expect("tangential compliance from partial forward solves");
    let full = slider
        .tangential_compliance_by_solves()
        .expect("tangential compliance from full solves");
    let tangential = relative_difference(&partial.tangential_m_per_n, &full.tangential_m_per_n);
    let cross = relative_difference(
        &partial.normal_from_tangential_m_per_n,
        &full.normal_from_tangential_m_per_n,
    );
    eprintln!(
        "relative differences: tangential {tangential:.2e}, cross {cross:.2e}; partial solves {:.3e} multiply-adds, {} supernodes",
        work.flops, work.supernodes_visited
    );
    assert!(
        tangential < 1e-10,
        "tangential tip compliance C_xx, partial vs full solves: relative difference {tangential:.2e}"
    );
    assert!(
        cross < 1e-10,
        "normal–tangential cross compliance C_zx, partial vs full solves: relative difference {cross:.2e}"
    );
    assert!(
        partial.tangential_m_per_n == partial.tangential_m_per_n.transpose(),
        "the tangential compliance is exactly symmetric"
    );
}
