//! Model files: a trained combined model (and optionally its pure-network baseline) as versioned JSON.
//!
//! ```json
//! { "format": "pushlab-model", "version": 1,
//!   "combined": { "network": [692 numbers], "normalization": {...}, "theta0": {"com_offset": [x, y], "h": h},
//!                 "loss_scale": {...}, "horizon": k },
//!   "pure_nn": { ... } | null,
//!   "training": { "report": {...}, "sources": ["path", ...], "pushlab_version": "0.1.0" } }
//! ```
//! Files are written atomically (a temporary file in the same folder, then a rename), so a crash never
//! leaves half a model behind.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::atomic_file::write_atomically;
use crate::learn::TrainingReport;
use crate::model::{CombinedModel, PureNnModel};

/// The `format` field of every model file.
pub const FORMAT: &str = "pushlab-model";
/// The version this pushlab writes and reads.
pub const VERSION: u32 = 1;

/// Where a model came from.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrainingMetadata {
    /// The combined model's training run.
    #[serde(default)]
    pub report: Option<TrainingReport>,
    /// The pure network's training run.
    #[serde(default)]
    pub pure_nn_report: Option<TrainingReport>,
    /// The recordings it was trained on.
    #[serde(default)]
    pub sources: Vec<String>,
    /// The pushlab version that trained it.
    #[serde(default)]
    pub pushlab_version: String,
}

/// A trained model as saved on disk.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFile {
    pub combined: CombinedModel,
    pub pure_nn: Option<PureNnModel>,
    pub training: TrainingMetadata,
}

#[derive(Serialize)]
struct OnDiskRef<'a> {
    format: &'a str,
    version: u32,
    combined: &'a CombinedModel,
    pure_nn: Option<&'a PureNnModel>,
    training: &'a TrainingMetadata,
}

#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OnDisk {
    #[allow(dead_code)]
    format: String,
    #[allow(dead_code)]
    version: u32,
    combined: CombinedModel,
    #[serde(default)]
    pure_nn: Option<PureNnModel>,
    #[serde(default)]
    training: TrainingMetadata,
}

/// Why a model file could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{path}: not a pushlab model file (the \"format\" field is {found}, expected \"{FORMAT}\")"
    )]
    NotAModel { path: PathBuf, found: String },
    #[error(
        "{path}: model file version {found}, but this pushlab reads version {VERSION}; retrain the model or use a matching pushlab"
    )]
    WrongVersion { path: PathBuf, found: String },
    #[error("{path}: line {line}, column {column}: {message}")]
    Malformed {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
}

impl ModelFile {
    /// Writes the model to `path` atomically.
    pub fn save(&self, path: &Path) -> Result<(), ModelFileError> {
        let io = |source| ModelFileError::Io {
            path: path.to_owned(),
            source,
        };
        let json = serde_json::to_vec_pretty(&OnDiskRef {
            format: FORMAT,
            version: VERSION,
            combined: &self.combined,
            pure_nn: self.pure_nn.as_ref(),
            training: &self.training,
        })
        .map_err(|e| io(std::io::Error::other(e)))?;
        write_atomically(path, &json).map_err(io)
    }

    /// Reads a model from `path`, checking its format, version and shapes.
    pub fn load(path: &Path) -> Result<Self, ModelFileError> {
        let bytes = std::fs::read(path).map_err(|source| ModelFileError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json(path, &bytes)
    }

    /// Parses a model from JSON bytes; `path` only names the source in errors.
    pub fn from_json(path: &Path, bytes: &[u8]) -> Result<Self, ModelFileError> {
        let malformed = |e: serde_json::Error| ModelFileError::Malformed {
            path: path.to_owned(),
            line: e.line(),
            column: e.column(),
            message: e.to_string(),
        };
        let header: Header = serde_json::from_slice(bytes).map_err(malformed)?;
        match header.format.as_deref() {
            Some(FORMAT) => {}
            other => {
                return Err(ModelFileError::NotAModel {
                    path: path.to_owned(),
                    found: other.map_or("missing".into(), |f| format!("\"{f}\"")),
                });
            }
        }
        match &header.version {
            Some(serde_json::Value::Number(n)) if n.as_u64() == Some(u64::from(VERSION)) => {}
            other => {
                return Err(ModelFileError::WrongVersion {
                    path: path.to_owned(),
                    found: other.as_ref().map_or("missing".into(), |v| v.to_string()),
                });
            }
        }
        let on_disk: OnDisk = serde_json::from_slice(bytes).map_err(malformed)?;
        Ok(Self {
            combined: on_disk.combined,
            pure_nn: on_disk.pure_nn,
            training: on_disk.training,
        })
    }
}
