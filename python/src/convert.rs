//! Library results → Python objects, through their serde form (`serde_json::Value`), so that a
//! field added or renamed in the library reaches Python without a change here. Numbers cross as
//! the f64/i64 they are (no text in between: exact and cheap); maps become dicts, sequences
//! lists, `None`/null `None`.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use serde_json::{Map, Value};

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
        Value::Object(map) => dict(py, map)?.into_any(),
    })
}

/// A JSON object as a Python dict.
pub fn dict<'py>(py: Python<'py>, map: &Map<String, Value>) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, v) in map {
        dict.set_item(key, to_py(py, v)?)?;
    }
    Ok(dict)
}

/// Columns of a speed–thrust curve, as `curve.csv` names them.
pub const CURVE_COLUMNS: [&str; 5] = [
    "speed_m_per_s",
    "thrust_n",
    "output_power_w",
    "efficiency",
    "stick_fraction",
];
