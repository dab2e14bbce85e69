//! Which input drives an output's spread: Spearman's rank correlation ρ between each sampled
//! input and the output (Pearson correlation of mid-ranks; ties get their mean rank), ranked by
//! |ρ|. Valid for monotone dependences; it needs no extra model runs (the Monte Carlo samples
//! are reused), unlike Sobol indices. |ρ| < 2/√n is within sampling noise.

use serde::Serialize;

/// Mid-ranks (1-based; ties share the mean of their ranks).
fn ranks(values: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut r = vec![0.0; values.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && values[order[j + 1]] == values[order[i]] {
            j += 1;
        }
        let mid = 0.5 * (i + j) as f64 + 1.0;
        for &k in &order[i..=j] {
            r[k] = mid;
        }
        i = j + 1;
    }
    r
}

/// Spearman's ρ of two equally long samples; `None` when either is constant (or n < 2).
pub fn spearman(x: &[f64], y: &[f64]) -> Option<f64> {
    if x.len() != y.len() || x.len() < 2 {
        return None;
    }
    let (rx, ry) = (ranks(x), ranks(y));
    let m = (x.len() as f64 + 1.0) / 2.0;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(&ry) {
        sxy += (a - m) * (b - m);
        sxx += (a - m) * (a - m);
        syy += (b - m) * (b - m);
    }
    (sxx > 0.0 && syy > 0.0).then(|| sxy / (sxx * syy).sqrt())
}

/// One input's rank correlation with one output.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    /// Input name (with unit).
    pub input: String,
    /// Spearman ρ (`None`: the input did not vary).
    pub spearman_rho: Option<f64>,
}

/// The inputs ranked by |ρ| with `output`, strongest first (constant inputs last).
/// `inputs[k]` is the name and the per-sample values of input k.
pub fn rank_inputs(inputs: &[(String, Vec<f64>)], output: &[f64]) -> Vec<Sensitivity> {
    let mut out: Vec<Sensitivity> = inputs
        .iter()
        .map(|(name, x)| Sensitivity {
            input: name.clone(),
            spearman_rho: spearman(x, output),
        })
        .collect();
    out.sort_by(|a, b| {
        let key = |s: &Sensitivity| s.spearman_rho.map_or(-1.0, f64::abs);
        key(b).total_cmp(&key(a))
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_monotone_relation_has_rank_correlation_one() {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| v.powi(3)).collect();
        assert_eq!(spearman(&x, &y), Some(1.0), "ρ of a cubic");
        let z: Vec<f64> = x.iter().map(|v| -v.exp()).collect();
        assert!(
            (spearman(&x, &z).unwrap() + 1.0).abs() < 1e-12,
            "ρ of a falling map"
        );
        assert_eq!(spearman(&x, &[1.0; 20]), None, "ρ with a constant");
    }

    #[test]
    fn the_input_that_drives_the_output_ranks_first() {
        // y = 10 a + b, a and b on interleaved grids: a dominates.
        let a: Vec<f64> = (0..50).map(|k| ((k * 7) % 50) as f64).collect();
        let b: Vec<f64> = (0..50).map(|k| ((k * 13) % 50) as f64).collect();
        let y: Vec<f64> = a.iter().zip(&b).map(|(a, b)| 10.0 * a + b).collect();
        let r = rank_inputs(
            &[
                ("b".into(), b),
                ("fixed".into(), vec![0.0; 50]),
                ("a".into(), a),
            ],
            &y,
        );
        assert_eq!(r[0].input, "a", "strongest input");
        assert_eq!(r[2].input, "fixed", "a constant input ranks last");
    }

    #[test]
    fn ties_get_mid_ranks() {
        assert_eq!(
            ranks(&[3.0, 1.0, 3.0, 2.0]),
            vec![3.5, 1.0, 3.5, 2.0],
            "mid-ranks"
        );
    }
}
