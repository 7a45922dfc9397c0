//! The labels file, `pushlab-labels.json`, kept beside the recordings it describes.
//!
//! ```json
//! {
//!   "format": "pushlab-labels",
//!   "version": 1,
//!   "schema": { "labels": [ { "name": "sticking", "colour": "#1f77b4", "hotkey": "3",
//!                              "kind": "range", "group": "contact mode" } ] },
//!   "recordings": {
//!     "push_000.csv": {
//!       "meta": { "object": "box", "split": "offline", "com_offset": [0.01, -0.005] },
//!       "segments": [ { "label": "sticking", "start": 0, "end": 40 } ],
//!       "events": [ { "label": "contact made", "frame": 2 } ]
//!     }
//!   }
//! }
//! ```
//!
//! Segments are half-open (`end` is one past the last frame). Reading checks the format name and
//! version first, so a file from a newer pushlab fails with a message naming both versions instead of
//! a confusing field error; syntax and type errors name the file, line and column; rule violations
//! (unknown label, overlapping exclusive labels) name the field. Writing is atomic: the new content
//! goes to a temporary file in the same folder, is flushed to disk, then renamed over the old file,
//! so a crash at any moment leaves either the old or the new file.

use crate::files as fs;
use crate::json_problem::{self, JsonProblem};
use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::files::write_atomically;

use super::schema::LabelSchema;
use super::{LabelSet, RecordingLabels};

/// The name of the labels file inside a recording set's folder.
pub const LABELS_FILE_NAME: &str = "pushlab-labels.json";
/// The value of the file's `"format"` field.
pub const FORMAT: &str = "pushlab-labels";
/// The version this pushlab writes, and the newest it reads.
pub const VERSION: u64 = 1;
/// The oldest version this pushlab reads (older ones would be migrated here).
pub const OLDEST_VERSION: u64 = 1;

/// Where the labels file of the recording set in `folder` lives.
pub fn path_in(folder: &Path) -> PathBuf {
    folder.join(LABELS_FILE_NAME)
}

/// Why a labels file could not be read or written. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum LabelFileError {
    /// The file could not be opened or read.
    #[error("cannot read labels file {}: {source}", path.display())]
    Read { path: PathBuf, source: io::Error },
    /// Not valid JSON, or a value of the wrong type.
    #[error("{}: {problem}", path.display())]
    Syntax { path: PathBuf, problem: JsonProblem },
    /// Valid JSON but not a pushlab labels file.
    #[error("{}: not a pushlab labels file: expected \"format\": \"{FORMAT}\", found {found}", path.display())]
    Format { path: PathBuf, found: String },
    /// A version this pushlab cannot read.
    #[error("{}: labels file version {found} is not supported: this pushlab reads versions {OLDEST_VERSION} to {VERSION}{hint}", path.display())]
    Version {
        path: PathBuf,
        found: String,
        hint: &'static str,
    },
    /// Well-formed but breaks a rule (unknown label, overlapping exclusive labels …).
    #[error("{}: {field}: {message}", path.display())]
    Invalid {
        path: PathBuf,
        field: String,
        message: String,
    },
    /// Another program wrote the file since it was read or last saved; saving would overwrite that.
    #[error(
        "{} was changed by another program since pushlab read it; your edits are kept in the app: overwrite the file with them, or reload it and drop them",
        path.display()
    )]
    ChangedOnDisk { path: PathBuf },
    /// Saving failed; the previous file on disk is unchanged.
    #[error("cannot save labels to {}: {source}; the previous file is unchanged", path.display())]
    Write { path: PathBuf, source: io::Error },
}

/// Version 1 of the file, as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileV1 {
    #[allow(dead_code)]
    format: String,
    #[allow(dead_code)]
    version: u64,
    #[serde(default)]
    schema: LabelSchema,
    #[serde(default)]
    recordings: BTreeMap<String, RecordingLabels>,
}

/// Version 1 of the file, as written (borrowing, so saving does not clone the labels).
#[derive(Serialize)]
struct FileV1Out<'a> {
    format: &'static str,
    version: u64,
    schema: &'a LabelSchema,
    recordings: BTreeMap<&'a str, &'a RecordingLabels>,
}

/// The text of the file at `path` as it is now, `None` when there is no file.
pub fn current_text(path: &Path) -> Result<Option<String>, LabelFileError> {
    match fs::read_to_string(path) {
        Ok(text) => Ok(Some(text)),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(LabelFileError::Read {
            path: path.to_owned(),
            source,
        }),
    }
}

/// Reads the labels file at `path`.
pub fn read(path: &Path) -> Result<LabelSet, LabelFileError> {
    let text = fs::read_to_string(path).map_err(|source| LabelFileError::Read {
        path: path.to_owned(),
        source,
    })?;
    parse(&text, path)
}

/// Reads the labels file at `path`, or starts an empty set with the default schema when there is
/// no file yet (a set that was never labelled). Any other problem is an error.
pub fn read_or_default(path: &Path) -> Result<LabelSet, LabelFileError> {
    match fs::metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(LabelSet::default()),
        _ => read(path),
    }
}

/// Parses the text of a labels file; `path` is only used in messages.
pub fn parse(text: &str, path: &Path) -> Result<LabelSet, LabelFileError> {
    let syntax = |problem: JsonProblem| LabelFileError::Syntax {
        path: path.to_owned(),
        problem,
    };
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| syntax(JsonProblem::of(&e)))?;
    let format = value.get("format");
    if format.and_then(|f| f.as_str()) != Some(FORMAT) {
        return Err(LabelFileError::Format {
            path: path.to_owned(),
            found: format.map_or_else(|| "no \"format\" field".into(), |f| f.to_string()),
        });
    }
    let version = match value.get("version") {
        Some(v) => v.as_u64().ok_or_else(|| LabelFileError::Version {
            path: path.to_owned(),
            found: v.to_string(),
            hint: " (the version must be a whole number)",
        })?,
        None => {
            return Err(LabelFileError::Version {
                path: path.to_owned(),
                found: "missing (no \"version\" field)".into(),
                hint: "",
            });
        }
    };
    // One arm per known version; an older version is migrated step by step to the current one here.
    let file: FileV1 = match version {
        1 => json_problem::from_file_bytes(text.as_bytes()).map_err(syntax)?,
        v if v > VERSION => {
            return Err(LabelFileError::Version {
                path: path.to_owned(),
                found: v.to_string(),
                hint: " (it was written by a newer pushlab; update pushlab to read it)",
            });
        }
        v => {
            return Err(LabelFileError::Version {
                path: path.to_owned(),
                found: v.to_string(),
                hint: " (no pushlab ever wrote this version)",
            });
        }
    };
    let mut set = LabelSet {
        schema: file.schema,
        recordings: file.recordings,
    };
    set.normalise_and_validate()
        .map_err(|(field, message)| LabelFileError::Invalid {
            path: path.to_owned(),
            field,
            message,
        })?;
    Ok(set)
}

/// The text of the labels file for `set`, in the current version. Recordings with no labels are
/// left out; keys are sorted so that files diff well.
pub fn to_json(set: &LabelSet) -> String {
    let out = FileV1Out {
        format: FORMAT,
        version: VERSION,
        schema: &set.schema,
        recordings: set
            .recordings
            .iter()
            .filter(|(_, r)| !r.is_empty())
            .map(|(k, r)| (k.as_str(), r))
            .collect(),
    };
    // Serialising plain maps, strings and finite numbers cannot fail; fall back to an empty
    // object text rather than panic if it ever did.
    let mut text = serde_json::to_string_pretty(&out).unwrap_or_else(|_| String::from("{}"));
    text.push('\n');
    text
}

/// Writes `set` to `path` atomically (see the module docs).
pub fn write(path: &Path, set: &LabelSet) -> Result<(), LabelFileError> {
    write_atomically(path, to_json(set).as_bytes()).map_err(|source| LabelFileError::Write {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
pub(crate) mod tests;
