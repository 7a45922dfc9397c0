//! Model files: a trained combined model (and optionally its pure-network baseline) as versioned JSON.
//!
//! ```json
//! { "format": "pushlab-model", "version": 3, "kind": "contact" | "paper",
//!   "combined": { ...the kind's data: "network": [numbers], normalisation, "loss_scale", "horizon"… },
//!   "pure_nn": { ... } | null,
//!   "training": { "report": {...}, "sources": ["path", ...], "pushlab_version": "0.1.0" } }
//! ```
//! Version 1 files (before model kinds) have no `kind` and open as `paper`; files before version 3
//! open without their training domain's pusher speeds (measured by an older, noise-prone rule). Every file read is
//! checked against the rules of [`validate`] before any of its numbers is used, and every error names
//! the file and the JSON path of the field (`combined.loss_scale.sigma_rot: must be > 0, found 0`).
//! Files are written atomically (a temporary file in the same folder, then a rename), so a crash
//! never leaves half a model behind.

mod contents;
pub mod validate;

pub use contents::{ModelFile, TrainingMetadata};

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::files::write_atomically;
use crate::json_problem::JsonProblem;
use std::sync::Arc;

use crate::model::{CombinedModel, ContactModel, ModelKind, PaperModel, PureNnModel};

/// The `format` field of every model file.
pub const FORMAT: &str = "pushlab-model";
/// The version this pushlab writes; it reads this one and every older one. Version 2 added the
/// kinds; version 3 measures the training domain's pusher speeds robustly
/// ([`crate::trajectory::Trajectory::pusher_speed`]), so older files' speeds are dropped on load
/// (see [`crate::domain::Domain::pusher_speed`]).
pub const VERSION: u32 = 3;
/// The first version whose training domain's pusher speeds are read.
const ROBUST_SPEED_VERSION: u64 = 3;

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
    /// Not JSON, or a field of the wrong type or shape; the message starts with the field's JSON
    /// path when there is one (`combined.horizon: invalid type: …`).
    #[error("{path}: {problem}")]
    Malformed { path: PathBuf, problem: JsonProblem },
    /// Well-formed, but a value breaks a rule of [`validate`].
    #[error("{path}: {field}: {message}")]
    Invalid {
        path: PathBuf,
        field: String,
        message: String,
    },
}

impl ModelFile {
    /// Writes the model to `path` atomically. A model that breaks a rule of [`validate`] is refused
    /// before anything is written: pushlab never writes a file it would not read back.
    pub fn save(&self, path: &Path) -> Result<(), ModelFileError> {
        let json = self.to_json(path)?;
        write_atomically(path, &json).map_err(|source| ModelFileError::Io {
            path: path.to_owned(),
            source,
        })
    }

    /// The file's JSON text, after checking every rule of [`validate`]; `path` names the file in
    /// errors.
    pub fn to_json(&self, path: &Path) -> Result<Vec<u8>, ModelFileError> {
        self.validate(path)?;
        let kind = self.combined.kind();
        let (pure_nn, training) = (self.pure_nn.as_ref(), &self.training);
        match &self.combined {
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
        .map_err(|e| ModelFileError::Io {
            path: path.to_owned(),
            source: std::io::Error::other(e),
        })
    }

    /// Reads a model from `path`, checking its format, version and shapes.
    pub fn load(path: &Path) -> Result<Self, ModelFileError> {
        let bytes = crate::files::read(path).map_err(|source| ModelFileError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json(path, &bytes)
    }

    /// Checks every rule of [`validate`]; `path` names the file in the error.
    pub fn validate(&self, path: &Path) -> Result<(), ModelFileError> {
        validate::check(self).map_err(|(field, message)| ModelFileError::Invalid {
            path: path.to_owned(),
            field,
            message,
        })
    }

    /// Parses a model from JSON bytes and checks it; `path` only names the source in errors.
    pub fn from_json(path: &Path, bytes: &[u8]) -> Result<Self, ModelFileError> {
        let header: Header = parse(path, bytes)?;
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
        let mut file = match kind {
            ModelKind::Paper => {
                let on_disk: OnDisk<PaperModel> = parse(path, bytes)?;
                Self {
                    combined: CombinedModel::Paper(Arc::new(on_disk.combined)),
                    pure_nn: on_disk.pure_nn,
                    training: on_disk.training,
                }
            }
            ModelKind::Contact => {
                let on_disk: OnDisk<ContactModel> = parse(path, bytes)?;
                Self {
                    combined: CombinedModel::Contact(Arc::new(on_disk.combined)),
                    pure_nn: on_disk.pure_nn,
                    training: on_disk.training,
                }
            }
        };
        if version < ROBUST_SPEED_VERSION
            && let Some(domain) = &mut file.training.domain
        {
            // Summed noisy steps, not comparable with today's speeds: unknown rather than wrong.
            domain.pusher_speed = None;
        }
        file.validate(path)?;
        Ok(file)
    }
}

/// Deserialises `bytes`, naming the JSON path of the field that did not fit.
fn parse<T: serde::de::DeserializeOwned>(path: &Path, bytes: &[u8]) -> Result<T, ModelFileError> {
    crate::json_problem::from_file_bytes(bytes).map_err(|problem| ModelFileError::Malformed {
        path: path.to_owned(),
        problem,
    })
}
