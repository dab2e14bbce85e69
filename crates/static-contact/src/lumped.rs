//! The lumped model of docs/physics.md §5–6: independent posts of stiffness k pressed with the total
//! load P on obstacle heights h_i, f_i = k ⟨h_i − z_s⟩₊ with z_s such that Σ f_i = P.

/// Post forces (N) and reference height z_s (m) of independent springs of stiffness
/// `stiffness_n_per_m` on obstacle heights `height_m` under total load `preload_n` > 0.
///
/// Exact water filling: with the heights sorted in decreasing order, the m highest posts touch
/// and z_s = (Σ_{top m} h − P/k)/m for the m with h_(m+1) ≤ z_s < h_(m).
pub fn independent_posts(
    height_m: &[f64],
    stiffness_n_per_m: f64,
    preload_n: f64,
) -> (Vec<f64>, f64) {
    let n = height_m.len();
    if n == 0 {
        return (Vec::new(), 0.0);
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| height_m[b].total_cmp(&height_m[a]));
    let squeeze = preload_n / stiffness_n_per_m;
    let mut sum = 0.0;
    let mut z = height_m[order[0]] - squeeze;
    for (m, &i) in order.iter().enumerate() {
        sum += height_m[i];
        z = (sum - squeeze) / (m + 1) as f64;
        let next_below = order.get(m + 1).is_none_or(|&j| height_m[j] <= z);
        if next_below {
            break;
        }
    }
    let forces = height_m
        .iter()
        .map(|h| stiffness_n_per_m * (h - z).max(0.0))
        .collect();
    (forces, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn water_filling_balances_the_load_and_leaves_low_posts_free() {
        let h = [3e-6, 0.0, 2e-6, 1e-6];
        let (f, z) = independent_posts(&h, 1e6, 3.0);
        assert!(
            (z - 1e-6).abs() < 1e-15,
            "reference height {z} m, expected 1 µm"
        );
        assert!(
            (f.iter().sum::<f64>() - 3.0).abs() < 1e-12,
            "total force equals the preload"
        );
        assert!(
            (f[0] - 2.0).abs() < 1e-9 && (f[2] - 1.0).abs() < 1e-9 && f[1] == 0.0,
            "forces {f:?}"
        );
    }

    #[test]
    fn a_large_load_puts_every_post_in_contact() {
        let h = [1e-9, -1e-9, 0.0];
        let (f, _) = independent_posts(&h, 1e6, 30.0);
        assert!(
            f.iter().all(|&x| x > 0.0),
            "all posts carry force under a large load: {f:?}"
        );
        assert!(
            (f.iter().sum::<f64>() - 30.0).abs() < 1e-9,
            "total force equals the preload"
        );
    }
}
