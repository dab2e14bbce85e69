//! Scene-file value types that carry a unit ("20 um") or a keyword ("auto", "fem").

use std::fmt;

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};

use crate::units::{Dimension, parse_quantity};

/// Deserialize a quantity string of `dimension` into SI; a bare number is refused.
fn deserialize_quantity<'de, D: Deserializer<'de>>(
    deserializer: D,
    dimension: Dimension,
) -> Result<f64, D::Error> {
    struct QuantityVisitor(Dimension);
    impl Visitor<'_> for QuantityVisitor {
        type Value = f64;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "a {} with a unit, like {}", self.0, self.0.example())
        }
        fn visit_str<E: de::Error>(self, text: &str) -> Result<f64, E> {
            parse_quantity(text, self.0).map_err(E::custom)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
            self.visit_f64(v as f64)
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
            self.visit_f64(v as f64)
        }
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
            Err(E::custom(format!(
                "expected a {} like {}, got the bare number {v}: write the unit",
                self.0,
                self.0.example()
            )))
        }
    }
    deserializer.deserialize_any(QuantityVisitor(dimension))
}

macro_rules! quantity_type {
    ($(#[$doc:meta])* $name:ident, $dimension:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name(pub f64);
        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                deserialize_quantity(deserializer, $dimension).map($name)
            }
        }
    };
}

quantity_type!(/// A length in metres.
    Length, Dimension::Length);
quantity_type!(/// A frequency in hertz.
    Frequency, Dimension::Frequency);
quantity_type!(/// A velocity in m/s.
    Velocity, Dimension::Velocity);
quantity_type!(/// A force in newtons.
    Force, Dimension::Force);
quantity_type!(/// A pressure or modulus in pascals.
    Pressure, Dimension::Pressure);
quantity_type!(/// A density in kg/m³.
    Density, Dimension::Density);
quantity_type!(/// A mass in kilograms.
    Mass, Dimension::Mass);
quantity_type!(/// A time in seconds.
    Time, Dimension::Time);

/// A peak voltage in volts, written `"125 V"` (prefixes `k`, `m`; V₀₋ₚ). Volts have no
/// [`Dimension`] of their own, since only this key carries them: the number and unit are read
/// here with the same rules (a bare number refused, the unit named in the message).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Voltage(pub f64);

/// Voltage units and their factors to volts, longest suffix first (`mV` before `V`).
const VOLTAGE_UNITS: [(&str, f64); 3] = [("kV", 1e3), ("mV", 1e-3), ("V", 1.0)];

impl Voltage {
    /// Read `"125 V"`, `"0.125 kV"` or `"125000 mV"` into volts.
    pub fn parse(text: &str) -> Result<f64, String> {
        let trimmed = text.trim();
        let expected = || format!("expected a voltage like \"125 V\" (peak), got \"{text}\"");
        let (factor, number) = VOLTAGE_UNITS
            .iter()
            .find_map(|(unit, factor)| trimmed.strip_suffix(unit).map(|n| (*factor, n.trim())))
            .ok_or_else(|| format!("{}: the unit is missing or not kV, V or mV", expected()))?;
        let value: f64 = number
            .parse()
            .map_err(|_| format!("{}: it does not start with a number", expected()))?;
        let volts = value * factor;
        if !volts.is_finite() {
            return Err(format!("{}: the number is not finite", expected()));
        }
        Ok(volts)
    }
}

impl<'de> Deserialize<'de> for Voltage {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(deserializer)?;
        match value.as_str() {
            Some(text) => Voltage::parse(text).map(Voltage).map_err(de::Error::custom),
            None => Err(de::Error::custom(format!(
                "expected a voltage like \"125 V\" (peak), got the bare value {value}: write the unit"
            ))),
        }
    }
}

/// A value that is either the keyword `"auto"` or a quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AutoOr<T> {
    /// Let the program choose (from geometry, stability limits, …).
    Auto,
    /// The user's value.
    Value(T),
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for AutoOr<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(deserializer)?;
        if value.as_str() == Some("auto") {
            return Ok(AutoOr::Auto);
        }
        T::deserialize(value)
            .map(AutoOr::Value)
            .map_err(|e| de::Error::custom(format!("{e} (or \"auto\")")))
    }
}

/// Post count of a square or rectangular array, written `"100x100"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PostCount {
    /// Posts along x (the wave's direction).
    pub along_x: u32,
    /// Posts along y.
    pub along_y: u32,
}

impl<'de> Deserialize<'de> for PostCount {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(deserializer)?;
        let text = value
            .as_str()
            .map_or_else(|| value.to_string(), str::to_owned);
        let fail = || {
            de::Error::custom(format!(
                "expected a post array like \"100x100\" (posts along x × along y), got {value}"
            ))
        };
        let (x, y) = text.split_once(['x', 'X', '×']).ok_or_else(fail)?;
        let decimal = |part: &str| -> Result<u32, D::Error> {
            let part = part.trim();
            if part.is_empty() || !part.bytes().all(|b| b.is_ascii_digit()) {
                return Err(de::Error::custom(format!(
                    "post array \"{text}\": counts are decimal integers like \"100x100\" (no signs, hexadecimal or other bases)"
                )));
            }
            part.parse().map_err(|_| fail())
        };
        let (along_x, along_y) = (decimal(x)?, decimal(y)?);
        if along_x == 0 || along_y == 0 {
            return Err(de::Error::custom(format!(
                "post array \"{text}\" must have at least one post each way"
            )));
        }
        Ok(Self { along_x, along_y })
    }
}

/// The effective contact ratio η: a number (the contract of
/// [`contact_springs::effective_ratio::check`]: finite, 0 < η ≤ 1.5, so a η the static stage
/// reports, even above 1, reads back) or `"fem"` (computed by the static stage).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EffectiveRatio {
    /// Computed by the static FEM contact stage.
    Fem,
    /// Given by the user.
    Given(f64),
}

impl<'de> Deserialize<'de> for EffectiveRatio {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let value = toml::Value::deserialize(deserializer)?;
        let number = match &value {
            toml::Value::String(s) if s == "fem" => return Ok(Self::Fem),
            toml::Value::Float(v) => *v,
            toml::Value::Integer(v) => *v as f64,
            _ => {
                return Err(de::Error::custom(format!(
                    "expected a number or \"fem\", got {value}"
                )));
            }
        };
        contact_springs::effective_ratio::check(number)
            .map(Self::Given)
            .map_err(de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::Voltage;

    #[test]
    fn voltages_parse_to_volts_and_a_missing_unit_is_refused() {
        for (text, volts) in [("125 V", 125.0), ("0.125 kV", 125.0), ("2500mV", 2.5)] {
            assert_eq!(Voltage::parse(text), Ok(volts), "{text}");
        }
        for text in ["125", "125 W", "V", "1e999 V"] {
            assert!(Voltage::parse(text).is_err(), "{text} must be refused");
        }
    }
}
