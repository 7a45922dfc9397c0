//! Values crossing into Python: numpy arrays of the core's series, and JSON-shaped values (settings,
//! metadata, schemas) as plain dicts and lists through Python's `json`, so that a dict holds exactly
//! the fields the core's files hold, under the same names.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pushlab_core::json_problem;
use pushlab_core::model::OnlineParams;
use pyo3::prelude::*;
use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::error::error;

/// A serialisable core value as Python dicts, lists, numbers and strings.
pub fn to_python<'py, T: Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(error)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// A Python value (dicts, lists, numbers, strings) read as a core value; `what` names it in errors.
pub fn from_python<T: DeserializeOwned>(value: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    let text: String = value
        .py()
        .import("json")?
        .call_method1("dumps", (value,))?
        .extract()?;
    json_problem::from_built(&text).map_err(|problem| error(format!("{what}: {problem}")))
}

/// A series as a 1-D array.
pub fn column<T: numpy::Element>(py: Python<'_>, values: Vec<T>) -> Bound<'_, PyArray1<T>> {
    values.into_pyarray(py)
}

/// Rows of `W` numbers as an `(N, W)` array.
pub fn rows<'py, const W: usize>(
    py: Python<'py>,
    rows: &[[f64; W]],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    let array = Array2::from_shape_vec((rows.len(), W), flat).map_err(error)?;
    Ok(array.into_pyarray(py))
}

/// θ_online as `[com_x, com_y, h]` (COM − geometric centre in the object frame, and Lynch's h;
/// metres).
pub fn theta_row(theta: &OnlineParams) -> [f64; 3] {
    [theta.com_offset[0], theta.com_offset[1], theta.h]
}
