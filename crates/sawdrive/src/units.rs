//! Human units at the edge: "20 um", "9.61 MHz", "1.1 m/s", "40 N", "125 V" → SI numbers. The
//! one home of unit parsing: every quantity of a scene, sweep, design or scatter file is read
//! here (the scene's value types in `scene/quantity.rs` and the studies' evaluator call
//! [`parse_quantity`]).
//!
//! A quantity is a number, optional white space, then a unit made of an optional SI prefix
//! (`T G M k m u µ n p f`) and a base unit of the expected dimension. The number without a unit
//! is refused for every dimensional field: silent unit mistakes are the costliest bugs here.

use std::fmt;

/// What a scene field measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// Metres (`m`, `mm`, `um`, `µm`, `nm`).
    Length,
    /// Hertz (`Hz`, `kHz`, `MHz`, `GHz`).
    Frequency,
    /// Metres per second (`m/s`, `mm/s`).
    Velocity,
    /// Newtons (`N`, `mN`, `kN`).
    Force,
    /// Pascals (`Pa`, `MPa`, `GPa`).
    Pressure,
    /// Kilograms per cubic metre (`kg/m3`, `kg/m^3`, `g/cm3`).
    Density,
    /// Kilograms, written with gram prefixes (`kg`, `g`, `mg`).
    Mass,
    /// Seconds (`s`, `ms`, `us`, `ns`, `ps`).
    Time,
    /// Volts, peak (`V`, `kV`, `mV`): the transducer's drive voltage V₀₋ₚ.
    Voltage,
}

impl Dimension {
    /// Base unit symbol to which SI prefixes attach.
    fn base_unit(self) -> &'static str {
        match self {
            Self::Length => "m",
            Self::Frequency => "Hz",
            Self::Velocity => "m/s",
            Self::Force => "N",
            Self::Pressure => "Pa",
            Self::Density => "kg/m3",
            Self::Mass => "g",
            Self::Time => "s",
            Self::Voltage => "V",
        }
    }

    /// Factor from the bare base unit to SI (grams to kilograms).
    fn base_to_si(self) -> f64 {
        match self {
            Self::Mass => 1e-3,
            _ => 1.0,
        }
    }

    /// An example of the accepted form, shown in errors.
    pub fn example(self) -> &'static str {
        match self {
            Self::Length => "\"20 um\"",
            Self::Frequency => "\"9.61 MHz\"",
            Self::Velocity => "\"1.1 m/s\"",
            Self::Force => "\"40 N\"",
            Self::Pressure => "\"66.5 GPa\"",
            Self::Density => "\"2329 kg/m3\"",
            Self::Mass => "\"29 mg\"",
            Self::Time => "\"1 ns\"",
            Self::Voltage => "\"125 V\"",
        }
    }
}

impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self {
            Self::Length => "length",
            Self::Frequency => "frequency",
            Self::Velocity => "velocity",
            Self::Force => "force",
            Self::Pressure => "pressure",
            Self::Density => "density",
            Self::Mass => "mass",
            Self::Time => "time",
            Self::Voltage => "voltage",
        };
        f.write_str(name)
    }
}

/// Why a quantity could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("expected a {dimension} like {example}, got \"{text}\": {reason}", example = dimension.example())]
pub struct UnitError {
    /// The text given.
    pub text: String,
    /// The dimension expected.
    pub dimension: Dimension,
    /// What is wrong with it.
    pub reason: String,
}

/// SI prefixes and their factors. `u` and `µ` (micro sign or Greek mu) both mean 10⁻⁶.
const PREFIXES: [(&str, f64); 12] = [
    ("T", 1e12),
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("", 1.0),
    ("m", 1e-3),
    ("u", 1e-6),
    ("µ", 1e-6),
    ("μ", 1e-6),
    ("n", 1e-9),
    ("p", 1e-12),
    ("f", 1e-15),
];

/// Whole-unit spellings that are not prefix + base.
fn special_unit(dimension: Dimension, unit: &str) -> Option<f64> {
    match (dimension, unit) {
        (Dimension::Density, "kg/m^3" | "kg m-3" | "kg/m³") => Some(1.0),
        (Dimension::Density, "g/cm3" | "g/cm^3" | "g/cm³") => Some(1e3),
        (Dimension::Frequency, "1/s") => Some(1.0),
        _ => None,
    }
}

/// Factor from `unit` to SI for `dimension`, if `unit` is one of its spellings.
fn unit_factor(dimension: Dimension, unit: &str) -> Option<f64> {
    if let Some(factor) = special_unit(dimension, unit) {
        return Some(factor);
    }
    let base = dimension.base_unit();
    if dimension == Dimension::Density {
        return (unit == base).then_some(1.0);
    }
    let prefix = unit.strip_suffix(base)?;
    PREFIXES
        .iter()
        .find(|(p, _)| *p == prefix)
        .map(|(_, f)| f * dimension.base_to_si())
}

/// Split "20.5e-3 mm" into ("20.5e-3", "mm"): the longest leading text that parses as a number.
fn split_number(text: &str) -> Option<(f64, &str)> {
    let numeric_len = text
        .char_indices()
        .take_while(|(_, c)| c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | 'e' | 'E'))
        .map(|(i, c)| i + c.len_utf8())
        .last()?;
    (1..=numeric_len)
        .rev()
        .filter(|&end| text.is_char_boundary(end))
        .find_map(|end| {
            text[..end]
                .parse::<f64>()
                .ok()
                .map(|v| (v, text[end..].trim()))
        })
}

/// Read a quantity of `dimension` from `text` and return it in SI units.
pub fn parse_quantity(text: &str, dimension: Dimension) -> Result<f64, UnitError> {
    let fail = |reason: String| UnitError {
        text: text.to_owned(),
        dimension,
        reason,
    };
    let trimmed = text.trim();
    let (value, unit) =
        split_number(trimmed).ok_or_else(|| fail("it does not start with a number".into()))?;
    if !value.is_finite() {
        return Err(fail("the number is not finite".into()));
    }
    if unit.is_empty() {
        return Err(fail(format!(
            "the unit is missing (base unit: {})",
            dimension.base_unit()
        )));
    }
    let factor = unit_factor(dimension, unit)
        .ok_or_else(|| fail(format!("'{unit}' is not a unit of {dimension}")))?;
    // Dividing by the exact power of ten keeps "20 um" at exactly 2e-5 (20 · 1e-6 is not).
    let si = if factor < 1.0 {
        value / (1.0 / factor).round()
    } else {
        value * factor
    };
    if !si.is_finite() {
        return Err(fail(format!(
            "it overflows to {si} in {}",
            dimension.base_unit()
        )));
    }
    if si != 0.0 && !si.is_normal() {
        return Err(fail(format!(
            "it underflows to the subnormal {si:e} {} (below {:e})",
            dimension.base_unit(),
            f64::MIN_POSITIVE
        )));
    }
    Ok(si)
}

/// Format an SI value with a sensible prefix for human output, e.g. 2e-5 m → "20 um".
pub fn format_quantity(value_si: f64, dimension: Dimension) -> String {
    let base = dimension.base_unit();
    if dimension == Dimension::Density || value_si == 0.0 || !value_si.is_finite() {
        return format!("{value_si} {base}");
    }
    let value = value_si / dimension.base_to_si();
    let (prefix, factor) = PREFIXES
        .iter()
        .filter(|(p, _)| !matches!(*p, "µ" | "μ"))
        .find(|(_, f)| value.abs() >= *f * 0.999_999_999)
        .copied()
        .unwrap_or(("f", 1e-15));
    let scaled = value / factor;
    let text = format!("{scaled:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    format!("{text} {prefix}{base}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voltages_parse_to_volts_and_a_missing_unit_is_refused() {
        for (text, volts) in [("125 V", 125.0), ("0.125 kV", 125.0), ("2500mV", 2.5)] {
            assert_eq!(
                parse_quantity(text, Dimension::Voltage),
                Ok(volts),
                "{text}"
            );
        }
        for text in ["125", "125 W", "V", "1e999 V"] {
            assert!(
                parse_quantity(text, Dimension::Voltage).is_err(),
                "{text} must be refused"
            );
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs()
    }

    #[test]
    fn the_briefs_examples_parse_to_si() {
        let cases = [
            ("20 um", Dimension::Length, 20e-6),
            ("20um", Dimension::Length, 20e-6),
            ("20 µm", Dimension::Length, 20e-6),
            ("9.61 MHz", Dimension::Frequency, 9.61e6),
            ("20 nm", Dimension::Length, 20e-9),
            ("1.1 m/s", Dimension::Velocity, 1.1),
            ("40 N", Dimension::Force, 40.0),
            ("0.5 mm", Dimension::Length, 0.5e-3),
            ("66.5 GPa", Dimension::Pressure, 66.5e9),
            ("2329 kg/m3", Dimension::Density, 2329.0),
            ("2.329 g/cm3", Dimension::Density, 2329.0),
            ("29 mg", Dimension::Mass, 29e-6),
            ("1e-9 s", Dimension::Time, 1e-9),
            ("-3.5e-1 N", Dimension::Force, -0.35),
        ];
        for (text, dimension, expected) in cases {
            let got = parse_quantity(text, dimension).unwrap();
            assert!(close(got, expected), "{text} → {got}, expected {expected}");
        }
    }

    #[test]
    fn missing_or_wrong_units_are_refused_with_the_expected_form() {
        let err = parse_quantity("20", Dimension::Length).unwrap_err();
        assert!(
            err.to_string().contains("unit is missing") && err.to_string().contains("\"20 um\""),
            "{err}"
        );
        let err = parse_quantity("20 kg", Dimension::Length).unwrap_err();
        assert!(
            err.to_string().contains("'kg' is not a unit of length"),
            "{err}"
        );
        assert!(
            parse_quantity("MHz", Dimension::Frequency).is_err(),
            "no number"
        );
        assert!(
            parse_quantity("inf N", Dimension::Force).is_err(),
            "not finite"
        );
        let err = parse_quantity("1e308 GHz", Dimension::Frequency).unwrap_err();
        assert!(err.to_string().contains("overflows"), "{err}");
        let err = parse_quantity("4.9e-324 MHz", Dimension::Frequency).unwrap_err();
        assert!(err.to_string().contains("subnormal"), "{err}");
    }

    #[test]
    fn formatting_picks_a_readable_prefix_and_round_trips() {
        assert_eq!(format_quantity(125.0, Dimension::Voltage), "125 V");
        assert_eq!(format_quantity(20e-6, Dimension::Length), "20 um");
        assert_eq!(format_quantity(9.61e6, Dimension::Frequency), "9.61 MHz");
        assert_eq!(format_quantity(40.0, Dimension::Force), "40 N");
        for (value, dimension) in [
            (1.82e-8, Dimension::Length),
            (2.9e-5, Dimension::Mass),
            (3979.0, Dimension::Velocity),
        ] {
            let text = format_quantity(value, dimension);
            assert!(
                close(parse_quantity(&text, dimension).unwrap(), value),
                "{text} round trip"
            );
        }
    }
}
