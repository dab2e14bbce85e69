//! Axis transforms: data are drawn in "axis space" (identity for linear axes, log10 for log
//! axes) on plain linear plotters coordinates, and tick labels are mapped back.

use crate::Scale;

/// Fraction of the data span added on each side so markers do not sit on the frame.
const RANGE_PADDING: f64 = 0.04;

/// Map a data value into axis space; `None` if it cannot be drawn on this scale.
pub(crate) fn to_axis(scale: Scale, value: f64) -> Option<f64> {
    match scale {
        Scale::Linear if value.is_finite() => Some(value),
        Scale::Log if value.is_finite() && value > 0.0 => Some(value.log10()),
        _ => None,
    }
}

/// Map an axis-space value back to data for a tick label.
pub(crate) fn label(scale: Scale, axis_value: f64) -> String {
    let value = match scale {
        Scale::Linear => axis_value,
        Scale::Log => 10f64.powf(axis_value),
    };
    format_number(value)
}

/// Compact number format: plain for moderate magnitudes, scientific otherwise.
pub(crate) fn format_number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 {
        "0".to_owned()
    } else if (1e-3..1e4).contains(&magnitude) {
        let text = format!("{value:.4}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        text.to_owned()
    } else {
        format!("{value:.2e}")
    }
}

/// Padded `[min, max]` of axis-space values; a degenerate span is widened to a unit span.
pub(crate) fn padded_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() || !hi.is_finite() {
        return None;
    }
    let span = hi - lo;
    if span <= f64::EPSILON * hi.abs().max(1.0) {
        let half = 0.5 * lo.abs().max(1.0);
        return Some((lo - half, hi + half));
    }
    Some((lo - RANGE_PADDING * span, hi + RANGE_PADDING * span))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axis_drops_non_positive_values() {
        assert_eq!(to_axis(Scale::Log, 0.0), None);
        assert_eq!(to_axis(Scale::Log, -1.0), None);
        assert_eq!(to_axis(Scale::Log, 100.0), Some(2.0));
        assert_eq!(to_axis(Scale::Linear, f64::NAN), None);
    }

    #[test]
    fn degenerate_range_is_widened() {
        let (lo, hi) = padded_range([3.0, 3.0].into_iter()).unwrap();
        assert!(
            lo < 3.0 && hi > 3.0,
            "range around a single value: {lo}..{hi}"
        );
    }

    #[test]
    fn numbers_are_formatted_compactly() {
        assert_eq!(format_number(0.5), "0.5");
        assert_eq!(format_number(2.0), "2");
        assert_eq!(format_number(1.5e-6), "1.50e-6");
    }
}
