//! The docs' links stay whole. README.md, ARCHITECTURE.md and every page of the guide (`docs/src`,
//! an mdBook) are read as markdown: every relative link and image must name a file that exists, and
//! every `#anchor` a heading of the markdown file it points into, by the anchor rule GitHub and
//! mdBook 0.5 share (see `markdown::heading_id`). Guide pages may link only inside `docs/src`, since mdBook
//! ships nothing else; every page there must be in `SUMMARY.md` and every entry of it must exist.
//! Links in code (fenced blocks and inline code) and `http(s)://` / `mailto:` links are skipped.
//!
//! A failure names the file, the line and the link. The checker's own tests (at the bottom, and in
//! `markdown`) write small documents into a scratch folder or a string and check that a broken link
//! or anchor is reported and a good one is not.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod markdown;

use std::collections::{HashMap, HashSet};
use std::path::{Component, Path, PathBuf};

use markdown::{Flavour, heading_ids, links};

/// The guide's sources, relative to the repository's root.
const GUIDE: &str = "docs/src";

#[test]
fn every_link_and_anchor_of_the_docs_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let problems = check_docs(root);
    assert!(
        problems.is_empty(),
        "broken links in the docs:\n{}",
        problems.join("\n")
    );
}

/// Checks README.md, ARCHITECTURE.md and the guide under `root`; one line per problem.
fn check_docs(root: &Path) -> Vec<String> {
    let guide = root.join(GUIDE);
    let mut files = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    files.extend(markdown_files(&guide));
    let mut checker = Checker::new(root);
    let mut problems = Vec::new();
    for file in &files {
        let confine = file.starts_with(&guide).then_some(guide.as_path());
        problems.extend(checker.check_file(file, confine));
    }
    problems.extend(checker.check_summary(&guide));
    problems
}

/// Every `.md` file under `dir`, sorted; none when `dir` does not exist (the SUMMARY check says so).
fn markdown_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return files;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(markdown_files(&path));
        } else if path.extension().is_some_and(|ext| ext == "md") {
            files.push(path);
        }
    }
    files.sort();
    files
}

/// Checks files' links, remembering the heading ids of the files it has read.
struct Checker {
    root: PathBuf,
    /// The heading ids of each markdown file read so far.
    ids: HashMap<PathBuf, HashSet<String>>,
}

impl Checker {
    fn new(root: &Path) -> Self {
        Self {
            root: root.to_path_buf(),
            ids: HashMap::new(),
        }
    }

    /// A path as the messages show it: relative to the root where it lies inside it.
    fn show(&self, path: &Path) -> String {
        path.strip_prefix(&self.root)
            .unwrap_or(path)
            .display()
            .to_string()
    }

    /// Checks the links of one file. With `confine`, every target must lie inside that folder.
    fn check_file(&mut self, file: &Path, confine: Option<&Path>) -> Vec<String> {
        let Ok(text) = std::fs::read_to_string(file) else {
            return vec![format!("{}: cannot be read", self.show(file))];
        };
        let mut problems = Vec::new();
        for link in links(&text) {
            if let Err(why) = self.check_link(file, &text, &link.dest, confine) {
                problems.push(format!(
                    "{}:{}: ({}): {why}",
                    self.show(file),
                    link.line,
                    link.dest
                ));
            }
        }
        problems
    }

    fn check_link(
        &mut self,
        file: &Path,
        text: &str,
        dest: &str,
        confine: Option<&Path>,
    ) -> Result<(), String> {
        let lower = dest.to_ascii_lowercase();
        if ["http://", "https://", "mailto:"]
            .iter()
            .any(|scheme| lower.starts_with(scheme))
        {
            return Ok(());
        }
        let (path, anchor) = match dest.split_once('#') {
            Some((path, anchor)) => (percent_decode(path), Some(percent_decode(anchor))),
            None => (percent_decode(dest), None),
        };
        if let Some(label) = dest.strip_prefix('[') {
            return Err(format!("no definition of the reference [{label}]"));
        }
        if path.is_empty() && anchor.is_none() {
            return Err("an empty link".to_owned());
        }
        if path.starts_with('/') {
            return Err("an absolute path: links must be relative to the file".to_owned());
        }
        let target = if path.is_empty() {
            file.to_path_buf()
        } else {
            normalize(&file.parent().unwrap_or(Path::new("")).join(&path))
        };
        if let Some(folder) = confine
            && !target.starts_with(folder)
        {
            return Err(format!(
                "{} lies outside {}, which is all mdBook ships",
                self.show(&target),
                self.show(folder)
            ));
        }
        if !target.exists() {
            return Err(format!("no such file: {}", self.show(&target)));
        }
        let Some(anchor) = anchor else {
            return Ok(());
        };
        if target.extension().is_none_or(|ext| ext != "md") {
            // Anchors into other files (a source file's line on GitHub) are not checked.
            return Ok(());
        }
        let flavour = if target.starts_with(self.root.join(GUIDE)) {
            Flavour::MdBook
        } else {
            Flavour::GitHub
        };
        let ids = match self.ids.get(&target) {
            Some(ids) => ids,
            None => {
                let target_text = if target == file {
                    text.to_owned()
                } else {
                    std::fs::read_to_string(&target)
                        .map_err(|err| format!("{} cannot be read: {err}", self.show(&target)))?
                };
                self.ids
                    .entry(target.clone())
                    .or_insert(heading_ids(&target_text, flavour))
            }
        };
        if ids.contains(&anchor) {
            Ok(())
        } else {
            Err(format!(
                "no heading of {} has the anchor #{anchor}",
                self.show(&target)
            ))
        }
    }

    /// Every page of the guide is in SUMMARY.md, and every entry of it is a page. (An entry that
    /// names no file, or none at all, is a broken link: [`Checker::check_file`] reports it.)
    fn check_summary(&self, guide: &Path) -> Vec<String> {
        let summary = guide.join("SUMMARY.md");
        let Ok(text) = std::fs::read_to_string(&summary) else {
            return vec![format!("{}: missing", self.show(&summary))];
        };
        let mut problems = Vec::new();
        let mut listed = HashSet::new();
        for link in links(&text) {
            let path = link.dest.split('#').next().unwrap_or_default();
            if path.is_empty() {
                continue;
            }
            let page = normalize(&guide.join(percent_decode(path)));
            let is_page = page.is_file() && page.extension().is_some_and(|ext| ext == "md");
            if page.exists() && !is_page {
                problems.push(format!(
                    "{}:{}: ({}): not a markdown page",
                    self.show(&summary),
                    link.line,
                    link.dest
                ));
            }
            listed.insert(page);
        }
        for page in markdown_files(guide) {
            if page != summary && !listed.contains(&page) {
                problems.push(format!(
                    "{}: not listed in {}, so the book leaves it out",
                    self.show(&page),
                    self.show(&summary)
                ));
            }
        }
        problems
    }
}

/// `%20`-style escapes decoded (a malformed one is kept as written).
fn percent_decode(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut index = 0;
    while index < bytes.len() {
        let hex = bytes
            .get(index + 1..index + 3)
            .and_then(|pair| std::str::from_utf8(pair).ok())
            .and_then(|pair| u8::from_str_radix(pair, 16).ok());
        match (bytes[index], hex) {
            (b'%', Some(byte)) => {
                out.push(byte);
                index += 3;
            }
            (byte, _) => {
                out.push(byte);
                index += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `a/b/../c` as `a/c`, without touching the file system.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other),
        }
    }
    out
}

// The checker's own tests.

/// An empty scratch folder for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("pushlab-docs-links-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_broken_link_and_a_broken_anchor_are_reported_with_file_and_line() {
    let dir = scratch("broken");
    write(
        &dir.join("README.md"),
        "# Title\n\
         \n\
         ## Second part\n\
         \n\
         A [good link](other.md#b-heading), [one here](#second-part), ![an image](img.png) and\n\
         [a folder](sub/).\n\
         A [missing file](missing.md) and a [missing anchor](other.md#nope).\n\
         A [link whose text\n\
         runs over two lines](gone.md) and [the web](https://example.com/x.md).\n",
    );
    write(&dir.join("other.md"), "# B heading\n");
    write(&dir.join("img.png"), "not really a PNG");
    write(&dir.join("sub/file.txt"), "");
    let problems = Checker::new(&dir).check_file(&dir.join("README.md"), None);
    assert_eq!(
        problems,
        vec![
            "README.md:7: (missing.md): no such file: missing.md".to_owned(),
            "README.md:7: (other.md#nope): no heading of other.md has the anchor #nope".to_owned(),
            "README.md:9: (gone.md): no such file: gone.md".to_owned(),
        ]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_guide_page_outside_the_summary_or_linking_outside_the_guide_is_reported() {
    let dir = scratch("summary");
    let guide = dir.join(GUIDE);
    write(
        &guide.join("SUMMARY.md"),
        "# Summary\n\n[Intro](intro.md)\n\n- [Part](part/page.md)\n- [Gone](gone.md)\n- [Draft]()\n- [Folder](part/)\n",
    );
    write(
        &guide.join("intro.md"),
        "# Intro\n\nSee [the page](part/page.md#page) and [the root](../../README.md).\n",
    );
    write(&guide.join("part/page.md"), "# Page\n");
    write(&guide.join("unlisted.md"), "# Unlisted\n");
    write(&dir.join("README.md"), "# Readme\n");
    write(
        &dir.join("ARCHITECTURE.md"),
        "# Architecture\n\nThe [guide](docs/src/intro.md#intro).\n",
    );
    let problems = check_docs(&dir);
    assert_eq!(
        problems,
        vec![
            "docs/src/SUMMARY.md:6: (gone.md): no such file: docs/src/gone.md".to_owned(),
            "docs/src/SUMMARY.md:7: (): an empty link".to_owned(),
            "docs/src/intro.md:3: (../../README.md): README.md lies outside docs/src, which is all \
             mdBook ships"
                .to_owned(),
            "docs/src/SUMMARY.md:8: (part/): not a markdown page".to_owned(),
            "docs/src/unlisted.md: not listed in docs/src/SUMMARY.md, so the book leaves it out"
                .to_owned(),
        ]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
