//! The results with a speed–thrust curve ([`DynamicResult`], [`RunResult`]) are native objects
//! whose parts are converted when read: a field (from the library's serde form) on attribute
//! access, the whole dict only when asked for (`data`), the curve once, as a numpy array over
//! one f64 buffer (no Python object per number). A call thus costs one small allocation instead
//! of a dict of every field, and reading a field runs no Python code: on the loaded 2-core test
//! machine, Python code between two millisecond-long Rust calls ran 5–10× slower than alone
//! (cold caches), so a Python wrapper class cost more than the conversions themselves.

use std::sync::OnceLock;

use pyo3::exceptions::{PyAttributeError, PyImportError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyByteArray, PyDict, PyList};
use serde_json::{Map, Value};
use stick_slip::CurvePoint;

use crate::convert;
use crate::errors::Failure;

/// The fields of a result, in the form the library returns them.
#[derive(Debug)]
pub enum Fields {
    /// Already serialised (a JSON object).
    Json(Map<String, Value>),
    /// The dynamic stage as it ran, serialised (as `sawdrive dynamic --json`) only when a field
    /// other than a lumped number is read: the serde form of the 50-point curve with its wave
    /// books is a few thousand map entries, ≈ 0.1 ms, a tenth of a period-average call.
    Stage {
        /// The stage (the reported model's result, the choices, the wave's books).
        stage: Box<sawdrive::pipeline::DynamicStage>,
        /// η used.
        effective_ratio: f64,
        /// Where η came from: `given` or `fem`.
        source: &'static str,
    },
}

impl Fields {
    /// The fields as one JSON object: for a stage, `sawdrive dynamic --json` (the reported
    /// model's result, the choices, the wave's books on every curve point) with
    /// `effective_ratio` and `effective_ratio_source`, bit for bit the command line's.
    fn to_json(&self) -> Result<Map<String, Value>, Failure> {
        match self {
            Fields::Json(map) => Ok(map.clone()),
            Fields::Stage {
                stage,
                effective_ratio,
                source,
            } => {
                let mut map = match serde_json::to_value(stage.json())? {
                    Value::Object(map) => map,
                    _ => Map::new(),
                };
                map.insert("effective_ratio".into(), Value::from(*effective_ratio));
                map.insert("effective_ratio_source".into(), Value::from(*source));
                Ok(map)
            }
        }
    }

    /// A number field of a lumped stage read straight from its result, without serialising
    /// it: the common reads (`r.stall_thrust_n`, …) then create one Python float. `None`: not
    /// such a field, a coupled run (whose JSON flattens another result), or not finite (serde
    /// writes those as null): the caller takes the JSON path, which gives the same value
    /// otherwise (the lumped result is flattened into the JSON without renames, and no other
    /// part of it has these names).
    fn number(&self, name: &str) -> Option<f64> {
        let Fields::Stage {
            stage,
            effective_ratio,
            ..
        } = self
        else {
            return None;
        };
        if stage.coupled.is_some() {
            return None;
        }
        let result = &stage.lumped.result;
        let value = match name {
            "stall_thrust_n" => result.stall_thrust_n,
            "no_load_speed_m_per_s" => result.no_load_speed_m_per_s,
            "efficiency" => result.efficiency,
            "stick_fraction" => result.stick_fraction,
            "contact_fraction" => result.contact_fraction,
            "max_output_power_w" => result.max_output_power_w,
            "effective_post_count" => result.effective_post_count,
            "mean_normal_force_per_post_n" => result.mean_normal_force_per_post_n,
            "tip_height_m" => result.tip_height_m,
            "friction_limit_n" => result.friction_limit_n,
            "crest_speed_m_per_s" => result.crest_speed_m_per_s,
            "wall_time_s" => result.wall_time_s,
            "effective_ratio" => *effective_ratio,
            _ => return None,
        };
        value.is_finite().then_some(value)
    }

    /// The fields and the curve (in the lumped model's columns) of a dynamic stage run at
    /// η = `effective_ratio` (from `source`); the fields are serialised when first read.
    pub fn of_stage(
        stage: sawdrive::pipeline::DynamicStage,
        effective_ratio: f64,
        source: &'static str,
    ) -> (Self, Vec<CurvePoint>) {
        let curve = stage.curve();
        let fields = Fields::Stage {
            stage: Box::new(stage),
            effective_ratio,
            source,
        };
        (fields, curve)
    }
}

/// The shared body of a result with a speed–thrust curve: its fields, the results folder
/// written (if any) and the curve.
#[derive(Debug)]
pub struct Outcome {
    fields: Fields,
    /// [`Fields::to_json`], made on the first read.
    json: OnceLock<Result<Map<String, Value>, Failure>>,
    folder: Option<String>,
    curve: Vec<CurvePoint>,
    /// The numpy (n, 2) speed–thrust array, made on the first read.
    array: OnceLock<Py<PyAny>>,
}

/// `numpy.ndarray`, imported once.
static NDARRAY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
/// `numpy.dtype("<f8")`, made once (a dtype object is not parsed again at each array).
static FLOAT64: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

impl Outcome {
    /// `fields`, the results folder written (if any) and the curve.
    pub fn new(fields: Fields, folder: Option<String>, curve: Vec<CurvePoint>) -> Self {
        Self {
            fields,
            json: OnceLock::new(),
            folder,
            curve,
            array: OnceLock::new(),
        }
    }

    /// The fields as JSON (serialised once).
    fn json(&self, py: Python<'_>) -> PyResult<&Map<String, Value>> {
        match self.json.get_or_init(|| self.fields.to_json()) {
            Ok(map) => Ok(map),
            Err(f) => Err(f.clone().into_pyerr(py)),
        }
    }

    /// Field `name` (`folder` included), converted now; `AttributeError` naming `class` if none.
    fn field<'py>(&self, py: Python<'py>, name: &str, class: &str) -> PyResult<Bound<'py, PyAny>> {
        if name == "folder" {
            return Ok(self.folder.as_deref().into_pyobject(py)?.into_any());
        }
        if let Some(value) = self.fields.number(name) {
            return Ok(value.into_pyobject(py)?.into_any());
        }
        match self.json(py)?.get(name) {
            Some(value) => convert::to_py(py, value),
            None => Err(PyAttributeError::new_err(format!(
                "{class} has no field {name:?}"
            ))),
        }
    }

    /// Every field as a new dict (SI units, as the command line's JSON), with `folder`.
    fn data<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = convert::dict(py, self.json(py)?)?;
        dict.set_item("folder", self.folder.as_deref())?;
        Ok(dict)
    }

    /// A numpy array (rows, `columns`) over little-endian f64 bytes of `values`, written
    /// straight into the one Python buffer the array keeps.
    fn numpy<'py>(
        &self,
        py: Python<'py>,
        columns: usize,
        values: impl Fn(&CurvePoint) -> Vec<f64>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let bytes = PyByteArray::new_with(py, 8 * columns * self.curve.len(), |buffer| {
            let numbers = self.curve.iter().flat_map(values);
            for (chunk, v) in buffer.chunks_exact_mut(8).zip(numbers) {
                chunk.copy_from_slice(&v.to_le_bytes());
            }
            Ok(())
        })?;
        let ndarray = NDARRAY.import(py, "numpy", "ndarray")?;
        let float64 = FLOAT64.get_or_try_init(py, || {
            let dtype = py.import("numpy")?.getattr("dtype")?.call1(("<f8",))?;
            PyResult::Ok(dtype.unbind())
        })?;
        let shape = (self.curve.len(), columns);
        ndarray.call1((shape, float64.bind(py), bytes))
    }

    /// The speed–thrust curve, numpy (n, 2): speed (m/s), thrust (N). Made once.
    fn curve<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        if let Some(array) = self.array.get() {
            return Ok(array.bind(py).clone());
        }
        let array = self.numpy(py, 2, |p| vec![p.speed_m_per_s, p.thrust_n])?;
        // Another thread may have set it meanwhile (the GIL was held throughout: it cannot).
        let _ = self.array.set(array.clone().unbind());
        Ok(array)
    }

    /// Every column of the curve, numpy (n, 5), [`convert::CURVE_COLUMNS`] order.
    fn table<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.numpy(py, convert::CURVE_COLUMNS.len(), |p| {
            vec![
                p.speed_m_per_s,
                p.thrust_n,
                p.output_power_w,
                p.efficiency,
                p.stick_fraction,
            ]
        })
    }

    /// The curve as the command line's JSON has it: a list of one dict per point.
    fn curve_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        // A stage's JSON has the command line's curve (with the wave's books on every point).
        let from_json = match &self.fields {
            Fields::Json(map) => map.get("curve").filter(|c| c.is_array()).cloned(),
            Fields::Stage { .. } => self
                .json(py)?
                .get("curve")
                .filter(|c| c.is_array())
                .cloned(),
        };
        let points = match from_json {
            Some(points) => points,
            None => {
                serde_json::to_value(&self.curve).map_err(|e| Failure::from(e).into_pyerr(py))?
            }
        };
        convert::to_py(py, &points)?
            .cast_into::<PyList>()
            .map_err(Into::into)
    }

    /// Every field and the curve (a list of dicts) as a plain dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = self.data(py)?;
        dict.set_item("curve", self.curve_points(py)?)?;
        Ok(dict)
    }

    /// The curve as a pandas DataFrame with the columns of `curve.csv`.
    fn curve_frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py
            .import("pandas")
            .map_err(|_| PyImportError::new_err("this needs pandas: pip install pandas"))?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("columns", convert::CURVE_COLUMNS.to_vec())?;
        pandas
            .getattr("DataFrame")?
            .call((self.table(py)?,), Some(&kwargs))
    }

    /// `Class(stall_thrust_n=…, …)`: the first scalar fields.
    fn repr(&self, py: Python<'_>, class: &str) -> PyResult<String> {
        let shown: Vec<String> = self
            .json(py)?
            .iter()
            .filter(|(_, v)| v.is_number() || v.is_string())
            .take(6)
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        Ok(format!("{class}({}, …)", shown.join(", ")))
    }

    /// Field names and methods, for `dir()` and completion.
    fn names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        let mut names: Vec<String> = self.json(py)?.keys().cloned().collect();
        names.extend(
            [
                "folder",
                "curve",
                "curve_points",
                "curve_frame",
                "data",
                "to_dict",
            ]
            .map(String::from),
        );
        names.sort();
        Ok(names)
    }
}

/// A native result class over [`Outcome`] (pyo3 classes cannot be generic).
macro_rules! curve_result {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[pyclass(frozen, module = "sawdrive._native")]
        #[derive(Debug)]
        pub struct $name(pub Outcome);

        #[pymethods]
        impl $name {
            /// Stall thrust (N): the v → 0⁺ limit of the thrust.
            #[getter]
            fn stall_thrust_n<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
                self.0.field(py, "stall_thrust_n", stringify!($name))
            }

            /// No-load speed (m/s): where the thrust falls to zero.
            #[getter]
            fn no_load_speed_m_per_s<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
                self.0.field(py, "no_load_speed_m_per_s", stringify!($name))
            }

            /// A field of the result (SI units, as the command line's JSON names it).
            fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
                self.0.field(py, name, stringify!($name))
            }

            /// Every field as a new dict (SI units, as the command line's JSON), with `folder`.
            #[getter]
            fn data<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                self.0.data(py)
            }

            /// The speed–thrust curve: numpy array (n, 2), columns speed (m/s), thrust (N).
            #[getter]
            fn curve<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
                self.0.curve(py)
            }

            /// The curve as the command line's JSON has it: one dict per point
            /// (`speed_m_per_s`, `thrust_n`, `output_power_w`, `efficiency`, `stick_fraction`).
            #[getter]
            fn curve_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
                self.0.curve_points(py)
            }

            /// The fields as a plain dict (JSON-compatible, SI units), `curve` as a list of
            /// dicts.
            fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
                self.0.to_dict(py)
            }

            /// The speed–thrust curve as a pandas DataFrame, one row per point, the columns of
            /// `curve.csv` (`speed_m_per_s`, `thrust_n`, `output_power_w`, `efficiency`,
            /// `stick_fraction`). Needs pandas.
            fn curve_frame<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
                self.0.curve_frame(py)
            }

            fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
                self.0.repr(py, stringify!($name))
            }

            fn __dir__(&self, py: Python<'_>) -> PyResult<Vec<String>> {
                self.0.names(py)
            }
        }
    };
}

curve_result!(
    /// The dynamic stage's result: every field of `sawdrive dynamic --json` as an attribute
    /// (`stall_thrust_n` N, `no_load_speed_m_per_s` m/s, `efficiency`, `stick_fraction`,
    /// `friction_limit_n` N, `crest_speed_m_per_s` m/s, `model`, `model_reason`, …), and
    /// `curve` (numpy (n, 2): speed m/s, thrust N), `effective_ratio` (η used),
    /// `effective_ratio_source` (`given` or `fem`), `folder` (results folder written, or None).
    /// Fields are converted when first read.
    DynamicResult
);

curve_result!(
    /// The whole pipeline's `summary.json` as attributes (`stall_thrust_n` N,
    /// `no_load_speed_m_per_s` m/s, `effective_contact_ratio`, `springs`, `timings`, …), `curve`
    /// (numpy (n, 2): speed m/s, thrust N) and `folder` (results folder, or None). Fields are
    /// converted when first read.
    RunResult
);
