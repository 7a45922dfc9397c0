//! The core's errors as Python exceptions: one class, `pushlab.PushlabError`, carrying the core's
//! message unchanged (it names the file, the line or field, and what was expected).

use std::fmt::Display;

use pyo3::PyErr;
use pyo3::exceptions::PyException;

pyo3::create_exception!(
    pushlab,
    PushlabError,
    PyException,
    "A file pushlab cannot read or write, or a value it cannot use. The message is pushlab's own: it names the file, the line or field, and what was expected."
);

/// A `PushlabError` with the core's message.
pub fn error<E: Display>(message: E) -> PyErr {
    PushlabError::new_err(message.to_string())
}
