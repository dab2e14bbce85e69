//! Library results → Python objects, through their serde form (`serde_json::Value`), so that a
//! field added or renamed in the library reaches Python without a change here. Numbers cross as
//! the f64/i64 they are (no text in between: exact and cheap); maps become dicts, sequences
//! lists, `None`/null `None`.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyList, PyString};
use serde_json::Value;

/// `value` as a Python object.
pub fn to_py<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let items = items
                .iter()
                .map(|v| to_py(py, v))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (key, v) in map {
                dict.set_item(key, to_py(py, v)?)?;
            }
            dict.into_any()
        }
    })
}

/// Columns of a speed–thrust curve ([`curve_columns`]), as `curve.csv` names them.
pub const CURVE_COLUMNS: [&str; 5] = [
    "speed_m_per_s",
    "thrust_n",
    "output_power_w",
    "efficiency",
    "stick_fraction",
];

/// A speed–thrust curve as little-endian f64 bytes, row by row, [`CURVE_COLUMNS`] in each row
/// (`numpy.frombuffer(b, "<f8").reshape(-1, 5)`): exact, and far cheaper than a list of dicts.
pub fn curve_columns<'py>(
    py: Python<'py>,
    curve: &[stick_slip::CurvePoint],
) -> Bound<'py, PyBytes> {
    let bytes: Vec<u8> = curve
        .iter()
        .flat_map(|p| {
            [
                p.speed_m_per_s,
                p.thrust_n,
                p.output_power_w,
                p.efficiency,
                p.stick_fraction,
            ]
        })
        .flat_map(f64::to_le_bytes)
        .collect();
    PyBytes::new(py, &bytes)
}
