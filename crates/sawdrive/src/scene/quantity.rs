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

quantity_type!(/// A peak voltage V₀₋ₚ in volts (`"125 V"`, `kV`, `mV`).
    Voltage, Dimension::Voltage);

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
