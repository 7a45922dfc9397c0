//! An in-memory tree of files: what a browser tab has instead of a disk.
//!
//! The page puts into it what it fetched or what a user dropped, under absolute paths
//! (`/pushlab/sample-data/box1-paper-ur-front/setting.json`); [`super`]'s calls read it on `wasm32`.
//! Folders are implied by the files under them, or made by [`Tree::create_dir_all`]. It is plain
//! Rust on every target, so its rules are tested on the desktop too.

use std::collections::{BTreeMap, BTreeSet};
use std::io;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

use super::{Entry, Metadata};

/// The tree the page's calls read (only used on `wasm32`; empty elsewhere).
pub static TREE: Tree = Tree::new();

/// Files by normal absolute path, and folders made empty.
pub struct Tree {
    inner: Mutex<Inner>,
}

struct Inner {
    files: BTreeMap<PathBuf, Arc<Vec<u8>>>,
    dirs: BTreeSet<PathBuf>,
}

/// `path` made absolute (under `/`) with `.` and `..` resolved by name, as a page has no current
/// folder and no links.
pub fn normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::from("/");
    for component in path.components() {
        match component {
            Component::Normal(name) => out.push(name),
            Component::ParentDir => {
                out.pop();
            }
            Component::RootDir | Component::CurDir | Component::Prefix(_) => {}
        }
    }
    out
}

fn not_found(path: &Path) -> io::Error {
    io::Error::new(
        io::ErrorKind::NotFound,
        format!("{} is not among the page's files", path.display()),
    )
}

impl Tree {
    /// An empty tree.
    pub const fn new() -> Self {
        Self {
            inner: Mutex::new(Inner {
                files: BTreeMap::new(),
                dirs: BTreeSet::new(),
            }),
        }
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        // A panic while holding the lock leaves plain maps that are still whole.
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Puts a file in the tree, replacing one at the same path.
    pub fn write(&self, path: &Path, bytes: Vec<u8>) {
        self.lock().files.insert(normal(path), Arc::new(bytes));
    }

    /// Makes a folder (empty until a file is written under it).
    pub fn create_dir_all(&self, path: &Path) {
        self.lock().dirs.insert(normal(path));
    }

    /// Takes a file out of the tree; `None` when there was none.
    pub fn remove(&self, path: &Path) -> Option<Vec<u8>> {
        let bytes = self.lock().files.remove(&normal(path))?;
        Some(Arc::try_unwrap(bytes).unwrap_or_else(|shared| shared.as_ref().clone()))
    }

    /// Takes every file under `folder` out of the tree, by path (a page's downloads).
    pub fn take_under(&self, folder: &Path) -> Vec<(PathBuf, Vec<u8>)> {
        let folder = normal(folder);
        let mut inner = self.lock();
        let paths: Vec<PathBuf> = (inner.files.range(folder.clone()..))
            .map(|(p, _)| p)
            .take_while(|p| p.starts_with(&folder))
            .cloned()
            .collect();
        paths
            .into_iter()
            .filter_map(|p| {
                let bytes = inner.files.remove(&p)?;
                Some((
                    p,
                    Arc::try_unwrap(bytes).unwrap_or_else(|b| b.as_ref().clone()),
                ))
            })
            .collect()
    }

    /// Removes every file and folder.
    pub fn clear(&self) {
        let mut inner = self.lock();
        inner.files.clear();
        inner.dirs.clear();
    }

    /// The whole file.
    pub fn read(&self, path: &Path) -> io::Result<Vec<u8>> {
        self.shared(path).map(|bytes| bytes.as_ref().clone())
    }

    /// The whole file, shared with the tree rather than copied (a bag of hundreds of megabytes
    /// read at offsets).
    pub fn shared(&self, path: &Path) -> io::Result<Arc<Vec<u8>>> {
        let path = normal(path);
        let found = self.lock().files.get(&path).cloned();
        match found {
            Some(bytes) => Ok(bytes),
            None if self.is_dir(&path) => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("{} is a folder", path.display()),
            )),
            None => Err(not_found(&path)),
        }
    }

    fn is_dir(&self, path: &Path) -> bool {
        let inner = self.lock();
        path == Path::new("/")
            || inner.dirs.iter().any(|d| d.starts_with(path))
            || inner
                .files
                .range(path.to_path_buf()..)
                .next()
                .is_some_and(|(f, _)| f != path && f.starts_with(path))
    }

    /// A file's size, or a folder.
    pub fn metadata(&self, path: &Path) -> io::Result<Metadata> {
        let path = normal(path);
        let len = self.lock().files.get(&path).map(|b| b.len() as u64);
        if let Some(len) = len {
            return Ok(Metadata { len, is_dir: false });
        }
        if self.is_dir(&path) {
            Ok(Metadata {
                len: 0,
                is_dir: true,
            })
        } else {
            Err(not_found(&path))
        }
    }

    /// The files and folders directly inside a folder, by name.
    pub fn read_dir(&self, path: &Path) -> io::Result<Vec<Entry>> {
        let path = normal(path);
        if !self.is_dir(&path) {
            return Err(not_found(&path));
        }
        let inner = self.lock();
        let mut children: BTreeMap<PathBuf, bool> = BTreeMap::new();
        let below = inner.files.keys().chain(inner.dirs.iter());
        for found in below.filter(|p| p.starts_with(&path) && **p != path) {
            let Ok(rest) = found.strip_prefix(&path) else {
                continue;
            };
            let mut parts = rest.components();
            let Some(first) = parts.next() else { continue };
            let is_dir = parts.next().is_some() || inner.dirs.contains(found);
            *children.entry(path.join(first)).or_default() |= is_dir;
        }
        Ok(children
            .into_iter()
            .map(|(path, is_dir)| Entry { path, is_dir })
            .collect())
    }

    /// Every file's path and size, by path (what the page holds, for its memory figure).
    pub fn files(&self) -> Vec<(PathBuf, u64)> {
        (self.lock().files.iter())
            .map(|(p, b)| (p.clone(), b.len() as u64))
            .collect()
    }
}

impl Default for Tree {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_are_what_files_are_under_and_list_their_children_once() {
        let tree = Tree::new();
        tree.write(Path::new("/site/set/setting.json"), b"{}".to_vec());
        tree.write(Path::new("/site/set/push_000.csv"), b"t\n".to_vec());
        tree.write(Path::new("site/other/a.csv"), b"abc".to_vec());
        tree.create_dir_all(Path::new("/site/empty"));

        assert_eq!(
            tree.metadata(Path::new("/site/other/a.csv")).expect("file"),
            Metadata {
                len: 3,
                is_dir: false
            }
        );
        assert!(tree.metadata(Path::new("/site/set")).expect("dir").is_dir);
        assert!(tree.metadata(Path::new("/site/empty")).expect("dir").is_dir);
        let error = tree
            .metadata(Path::new("/site/se"))
            .expect_err("a prefix is no folder");
        assert_eq!(error.to_string(), "/site/se is not among the page's files");

        let listed = tree.read_dir(Path::new("/site")).expect("listed");
        let names: Vec<(String, bool)> = listed
            .iter()
            .map(|e| (e.path.display().to_string(), e.is_dir))
            .collect();
        assert_eq!(
            names,
            [
                ("/site/empty".to_owned(), true),
                ("/site/other".to_owned(), true),
                ("/site/set".to_owned(), true)
            ]
        );
        let in_set = tree
            .read_dir(Path::new("/site/./set/../set"))
            .expect("listed");
        assert_eq!(in_set.len(), 2);
        assert!(in_set.iter().all(|e| !e.is_dir));
        assert_eq!(
            tree.read(Path::new("/site/set/push_000.csv"))
                .expect("read"),
            b"t\n"
        );
        assert_eq!(
            tree.read(Path::new("/site/set"))
                .expect_err("a folder")
                .to_string(),
            "/site/set is a folder"
        );
        let taken = tree.take_under(Path::new("/site/set"));
        let names: Vec<String> = taken.iter().map(|(p, _)| p.display().to_string()).collect();
        assert_eq!(names, ["/site/set/push_000.csv", "/site/set/setting.json"]);
        assert!(tree.metadata(Path::new("/site/set")).is_err(), "taken out");
        assert!(
            tree.metadata(Path::new("/site/other/a.csv")).is_ok(),
            "left"
        );
    }
}
