//! Which files make a bag: an `.mcap` file, or a rosbag2 folder and the `.mcap` files its
//! `metadata.yaml` lists.

use std::path::{Path, PathBuf};

use super::error::BagError;
use super::mcap::{Bytes, Source};
use super::problem::BagProblem;
use crate::files;

/// Whether `path` looks like a bag: an `.mcap` file, or a folder with `metadata.yaml`.
pub fn is_bag(path: &Path) -> bool {
    if files::is_dir(path) {
        files::is_file(&path.join("metadata.yaml"))
    } else {
        path.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("mcap"))
    }
}

/// The `.mcap` files of a bag, in recording order: the file itself, or those a rosbag2 folder's
/// `metadata.yaml` lists (all `.mcap` files of the folder by name when it lists none).
pub fn bag_files(path: &Path) -> Result<Vec<PathBuf>, BagError> {
    if !files::is_dir(path) {
        return Ok(vec![path.to_path_buf()]);
    }
    let metadata = path.join("metadata.yaml");
    let text = files::read_to_string(&metadata).map_err(|e| BagError::io(&metadata, e))?;
    let mut mcaps: Vec<PathBuf> = listed_files(&text)
        .into_iter()
        .map(|name| path.join(name))
        .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
        .collect();
    if mcaps.is_empty() {
        let entries = files::read_dir(path).map_err(|e| BagError::io(path, e))?;
        mcaps = entries
            .into_iter()
            .map(|e| e.path)
            .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
            .collect();
        mcaps.sort();
    }
    if mcaps.is_empty() {
        return Err(BagError::Problem {
            path: path.to_path_buf(),
            problem: BagProblem::NoMcapFiles,
        });
    }
    Ok(mcaps)
}

/// The entries of `relative_file_paths:` in a rosbag2 `metadata.yaml` (a YAML block list of plain
/// names; a YAML library would be a dependency for three lines).
fn listed_files(yaml: &str) -> Vec<String> {
    let mut files = Vec::new();
    let mut in_list = None;
    for line in yaml.lines() {
        let indent = line.len() - line.trim_start().len();
        let trimmed = line.trim();
        if trimmed.starts_with("relative_file_paths:") {
            in_list = Some(indent);
            continue;
        }
        let Some(list_indent) = in_list else { continue };
        if let Some(item) = trimmed.strip_prefix("- ") {
            files.push(item.trim().trim_matches(['"', '\'']).to_owned());
        } else if !trimmed.is_empty() && indent <= list_indent {
            in_list = None;
        }
    }
    files
}

/// Runs `read` on one `.mcap` file of a bag — opened for reading at offsets, or the bytes given
/// (one file held in memory) — and names the file in what goes wrong. A read stopped by its progress
/// is [`BagProblem::Cancelled`], which the loader says as its own cancel.
pub(super) fn read_file<T>(
    file: &Path,
    bytes: Option<&[u8]>,
    read: impl FnOnce(&dyn Source) -> Result<T, BagProblem>,
) -> Result<T, BagError> {
    let fail = |problem| BagError::problem(file, problem);
    match bytes {
        Some(bytes) => read(&Bytes(bytes)).map_err(fail),
        None => {
            let source = files::Positioned::open(file).map_err(|e| BagError::io(file, e))?;
            read(&source).map_err(fail)
        }
    }
}
