//! The model a command learns with when `--model` is not given: the app's default, built into the
//! binary, so that `pushlab live` and `pushlab suggest` work from any folder.

use std::path::{Path, PathBuf};

use anyhow::anyhow;
use pushlab_core::model_file::ModelFile;

use crate::cli::exit::Failure;

const DEFAULT_MODEL: &[u8] = include_bytes!("../../assets/default-model.json");
const DEFAULT_MODEL_NAME: &str = "assets/default-model.json";

/// The model file named, or the built-in default; its name for messages.
pub fn load_model(path: Option<&Path>) -> Result<(ModelFile, String), Failure> {
    let failed = |e| Failure::Failed(anyhow!("{e}"));
    match path {
        Some(path) => Ok((
            ModelFile::load(path).map_err(failed)?,
            path.display().to_string(),
        )),
        None => Ok((
            ModelFile::from_json(&PathBuf::from(DEFAULT_MODEL_NAME), DEFAULT_MODEL)
                .map_err(failed)?,
            format!("the default model ({DEFAULT_MODEL_NAME})"),
        )),
    }
}
