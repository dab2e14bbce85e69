//! serde helpers for numbers that serde_json wrote as `null` because they were NaN (not
//! computed): a leaf module, so that the studies' result types and the report that reads and
//! draws them do not import each other.

/// Deserialises a number that serde_json wrote as `null` because it was NaN (not computed).
pub fn f64_or_nan<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::NAN))
}

/// Deserialises a pair of numbers, either of which may have been written as `null` (NaN).
pub fn pair_or_nan<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<[f64; 2], D::Error> {
    use serde::Deserialize;
    let [a, b] = <[Option<f64>; 2]>::deserialize(deserializer)?;
    Ok([a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)])
}
