//! Pareto front of two objectives, both maximised (e.g. stall thrust and no-load speed): point
//! i is on the front if no other point is ≥ in both and > in one. O(n log n): sort by the first
//! objective descending, keep the running maximum of the second.

/// Indices of the non-dominated points (both coordinates maximised), in order of decreasing
/// first coordinate. Non-finite points are never on the front.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        points[b]
            .0
            .total_cmp(&points[a].0)
            .then(points[b].1.total_cmp(&points[a].1))
    });
    let mut front = Vec::new();
    let mut best_second = f64::NEG_INFINITY;
    for i in order {
        if points[i].1 > best_second {
            front.push(i);
            best_second = points[i].1;
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_points_are_left_off_the_front() {
        let pts = [
            (1.0, 5.0),
            (2.0, 4.0),
            (1.5, 3.0),
            (3.0, 1.0),
            (2.0, 4.0),
            (0.5, 5.0),
        ];
        let front = pareto_front(&pts);
        assert_eq!(front, vec![3, 1, 0], "front of thrust/speed pairs");
    }
}
