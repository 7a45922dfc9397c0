//! Model files: a trained combined model (and optionally its pure-network baseline) as versioned JSON.
//!
//! ```json
//! { "format": "pushlab-model", "version": 2, "kind": "contact" | "paper",
//!   "combined": { ...the kind's data: "network": [numbers], normalisation, "loss_scale", "horizon"… },
//!   "pure_nn": { ... } | null,
//!   "training": { "report": {...}, "sources": ["path", ...], "pushlab_version": "0.1.0" } }
//! ```
//! Version 1 files (before model kinds) have no `kind` and open as `paper`. Files are written
//! atomically (a temporary file in the same folder, then a rename), so a crash never leaves half a
//! model behind.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::atomic_file::write_atomically;
use crate::experiment::Domain;
use crate::learn::TrainingReport;
use std::sync::Arc;

use crate::model::{CombinedModel, ContactModel, ModelKind, PaperModel, PureNnModel};

/// The `format` field of every model file.
pub const FORMAT: &str = "pushlab-model";
/// The version this pushlab writes; it reads this one and every older one.
pub const VERSION: u32 = 2;

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
    /// The objects, pushers, frame rates and speeds it was trained on (`null` in files written before
    /// pushlab recorded it): see [`crate::experiment::Domain`].
    #[serde(default)]
    pub domain: Option<Domain>,
}

/// A trained model as saved on disk.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFile {
    pub combined: CombinedModel,
    pub pure_nn: Option<PureNnModel>,
    pub training: TrainingMetadata,
}

#[derive(Serialize)]
struct OnDiskRef<'a, C> {
    format: &'a str,
    version: u32,
    kind: ModelKind,
    combined: &'a C,
    pure_nn: Option<&'a PureNnModel>,
    training: &'a TrainingMetadata,
}

#[derive(Deserialize)]
struct Header {
    format: Option<String>,
    version: Option<serde_json::Value>,
    kind: Option<serde_json::Value>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, bound = "C: serde::de::DeserializeOwned")]
struct OnDisk<C> {
    #[allow(dead_code)]
    format: String,
    #[allow(dead_code)]
    version: u32,
    #[allow(dead_code)]
    #[serde(default)]
    kind: Option<ModelKind>,
    combined: C,
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
        "{path}: model file version {found}, but this pushlab reads versions 1 to {VERSION}; it was written by a newer pushlab (update pushlab) or is not a model file"
    )]
    WrongVersion { path: PathBuf, found: String },
    #[error(
        "{path}: \"kind\" is {found}, expected one of \"contact\", \"paper\" (written by a newer pushlab?)"
    )]
    UnknownKind { path: PathBuf, found: String },
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
        let kind = self.combined.kind();
        let (pure_nn, training) = (self.pure_nn.as_ref(), &self.training);
        let json = match &self.combined {
            CombinedModel::Paper(m) => serde_json::to_vec_pretty(&OnDiskRef {
                format: FORMAT,
                version: VERSION,
                kind,
                combined: m.as_ref(),
                pure_nn,
                training,
            }),
            CombinedModel::Contact(m) => serde_json::to_vec_pretty(&OnDiskRef {
                format: FORMAT,
                version: VERSION,
                kind,
                combined: m.as_ref(),
                pure_nn,
                training,
            }),
        }
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
        let version = match &header.version {
            Some(serde_json::Value::Number(n))
                if n.as_u64()
                    .is_some_and(|v| (1..=u64::from(VERSION)).contains(&v)) =>
            {
                n.as_u64().unwrap_or(1)
            }
            other => {
                return Err(ModelFileError::WrongVersion {
                    path: path.to_owned(),
                    found: other.as_ref().map_or("missing".into(), |v| v.to_string()),
                });
            }
        };
        // Version 1 predates model kinds: every such file is the paper's model.
        let kind = match (&header.kind, version) {
            (None, _) => ModelKind::Paper,
            (Some(serde_json::Value::String(name)), _) => {
                ModelKind::from_name(name).ok_or_else(|| ModelFileError::UnknownKind {
                    path: path.to_owned(),
                    found: format!("\"{name}\""),
                })?
            }
            (Some(other), _) => {
                return Err(ModelFileError::UnknownKind {
                    path: path.to_owned(),
                    found: other.to_string(),
                });
            }
        };
        let file = match kind {
            ModelKind::Paper => {
                let on_disk: OnDisk<PaperModel> =
                    serde_json::from_slice(bytes).map_err(malformed)?;
                Self {
                    combined: CombinedModel::Paper(Arc::new(on_disk.combined)),
                    pure_nn: on_disk.pure_nn,
                    training: on_disk.training,
                }
            }
            ModelKind::Contact => {
                let on_disk: OnDisk<ContactModel> =
                    serde_json::from_slice(bytes).map_err(malformed)?;
                Self {
                    combined: CombinedModel::Contact(Arc::new(on_disk.combined)),
                    pure_nn: on_disk.pure_nn,
                    training: on_disk.training,
                }
            }
        };
        Ok(file)
    }
}
