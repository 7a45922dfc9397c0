//! pushlab from Python: the `pushlab` package's native module (`pushlab._native`), built with maturin
//! into an abi3 wheel.
//!
//! Nothing here computes anything of its own: every function hands its arguments to the core
//! (`pushlab-core`) and turns the answer into Python objects and numpy arrays, so that a script's
//! numbers are the CLI's and the app's. The modules, one concern each:
//! - [`error`]: the core's errors as `pushlab.PushlabError`, message unchanged;
//! - [`convert`]: numpy arrays and JSON-shaped values (settings, metadata) to and from Python;
//! - [`recording`]: `pushlab.load` and `pushlab.Recording`;
//! - [`labels`]: `pushlab.Labels`, a folder's labels file as the core's document;
//! - [`model`]: `pushlab.Model` (load, train, save, predict) and [`online`]: its online runs;
//! - [`simulate`]: `pushlab.simulate`, recording sets with a known COM and `h`;
//! - [`control`]: `pushlab.Controller`, push to goal on poses a script gives.

// PyO3 hands each argument over as an owned value it extracted from Python (a `PathBuf` from a str
// or path-like, a `Vec` from a list), so Python-facing functions take them by value.
#![allow(clippy::needless_pass_by_value)]

mod control;
mod convert;
mod error;
mod labels;
mod model;
mod online;
mod recording;
mod simulate;

use pyo3::prelude::*;

/// pushlab's core from Python: recordings, labels, the combined push model and its online learning.
#[pymodule(name = "_native")]
mod native {
    #[pymodule_export]
    use super::control::Controller;
    #[pymodule_export]
    use super::error::PushlabError;
    #[pymodule_export]
    use super::labels::Labels;
    #[pymodule_export]
    use super::model::{Model, Prediction};
    #[pymodule_export]
    use super::online::OnlineRun;
    #[pymodule_export]
    use super::recording::{Recording, load};
    #[pymodule_export]
    use super::simulate::simulate;

    /// The version of pushlab (and of its core) this module was built from.
    #[allow(non_upper_case_globals)]
    #[pymodule_export]
    const __version__: &str = env!("CARGO_PKG_VERSION");
}
