//! The architecture, checked: the layers ARCHITECTURE.md declares are the layers the code has, no
//! module imports another that imports it back (file by file, and folder by folder: no two sibling
//! modules' subtrees import each other), and no source file outgrows 600 lines.
//!
//! Why a test: rerun splits its viewer into crates so that cargo refuses an upward import; inside one
//! crate nothing does, and a cycle creeps in with one convenient `use super::…`. The layers are read
//! from ARCHITECTURE.md's ```` ```layers PATH ```` blocks, so the document and the check cannot
//! disagree.

mod graph;
mod source;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use graph::{Crate, ModPath, cycles};

/// The most lines of non-test code a source file may have.
const MAX_LINES: usize = 600;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The crates of the workspace, by their source root file.
fn crates() -> Vec<(&'static str, Crate)> {
    [
        ("crates/pushlab-core/src", "crates/pushlab-core/src/lib.rs"),
        ("src (the app, lib.rs)", "src/lib.rs"),
        ("src (the CLI, main.rs)", "src/main.rs"),
        ("crates/pushlab-py/src", "crates/pushlab-py/src/lib.rs"),
    ]
    .into_iter()
    .map(|(name, file)| (name, Crate::read(&root().join(file))))
    .collect()
}

fn shown(path: &ModPath) -> String {
    if path.is_empty() {
        "crate".to_owned()
    } else {
        path.join("::")
    }
}

#[test]
fn no_module_imports_a_module_that_imports_it_back() {
    let mut problems = Vec::new();
    for (name, krate) in crates() {
        for cycle in cycles(krate.edges()) {
            let links: Vec<String> = cycle
                .iter()
                .flat_map(|a| {
                    krate.edges()[a]
                        .iter()
                        .filter(|b| cycle.contains(b))
                        .map(move |b| format!("{} → {}", shown(a), shown(b)))
                })
                .collect();
            problems.push(format!("{name}: {}", links.join(", ")));
        }
    }
    assert!(
        problems.is_empty(),
        "import cycles (move what both sides need into a module below them):\n{}",
        problems.join("\n")
    );
}

/// The edges between sibling subtrees: `a → b` becomes `A → B`, where `A` and `B` are the children
/// of their deepest common ancestor holding `a` and `b` (`recording::bag::split → recording::error` is
/// `recording::bag → recording::error`). An edge into an ancestor (`recording::bag::split →
/// recording`) joins no siblings and is left out.
fn sibling_edges(
    edges: &BTreeMap<ModPath, BTreeSet<ModPath>>,
) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
    let mut siblings: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    for (a, targets) in edges {
        for b in targets {
            let common = a.iter().zip(b).take_while(|(x, y)| x == y).count();
            if a.len() > common && b.len() > common {
                siblings
                    .entry(a[..=common].to_vec())
                    .or_default()
                    .insert(b[..=common].to_vec());
            }
        }
    }
    siblings
}

/// Loops between sibling folders that were there when the check came and are not untangled yet: the
/// crate, then the modules of the loop. Any other loop fails the check, and so does one of these
/// that grew or went away (strike it off the list then).
const KNOWN_FOLDER_LOOPS: &[(&str, &[&str])] =
    &[("src (the app, lib.rs)", &["app::panels", "app::view"])];

#[test]
fn no_folder_imports_a_sibling_that_imports_it_back() {
    let mut problems = Vec::new();
    let mut known_seen = Vec::new();
    for (name, krate) in crates() {
        let siblings = sibling_edges(krate.edges());
        for cycle in cycles(&siblings) {
            let modules: Vec<String> = cycle.iter().map(shown).collect();
            if let Some(known) = KNOWN_FOLDER_LOOPS
                .iter()
                .find(|(krate, looped)| *krate == name && *looped == modules.as_slice())
            {
                known_seen.push(known);
                continue;
            }
            let mut links = Vec::new();
            for a in &cycle {
                for b in siblings[a].iter().filter(|b| cycle.contains(b)) {
                    // One file-to-file edge that makes the link, for the message.
                    let example = krate.edges().iter().find_map(|(from, targets)| {
                        let to = targets
                            .iter()
                            .find(|to| from.starts_with(a) && to.starts_with(b))?;
                        Some(format!("{} → {}", shown(from), shown(to)))
                    });
                    links.push(format!(
                        "{} → {} ({})",
                        shown(a),
                        shown(b),
                        example.unwrap_or_default()
                    ));
                }
            }
            problems.push(format!("{name}: {}", links.join(", ")));
        }
    }
    for known in KNOWN_FOLDER_LOOPS {
        if !known_seen.contains(&known) {
            problems.push(format!(
                "{}: the known loop {} is gone or changed: take it off KNOWN_FOLDER_LOOPS",
                known.0,
                known.1.join(", ")
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "modules whose subtrees import each other (let the lower one return its own type and the \
         upper one wrap it):\n{}",
        problems.join("\n")
    );
}

/// The layers declared for `scope` in ARCHITECTURE.md: each module's line number, lowest first.
fn declared_layers(scope: &str) -> BTreeMap<String, usize> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let fence = format!("```layers {scope}");
    let start = text
        .find(&fence)
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no ```layers {scope} block"));
    let body = &text[start + fence.len()..];
    let body = &body[..body.find("```").expect("the layers block is closed")];
    let mut layers = BTreeMap::new();
    for (line, modules) in body.lines().filter(|l| !l.trim().is_empty()).enumerate() {
        for module in modules.split_whitespace() {
            layers.insert(module.to_owned(), line);
        }
    }
    layers
}

/// Checks that every top-level module below `prefix` in `krate` imports only from its own layer or
/// those below, as ARCHITECTURE.md's `scope` block declares them.
fn check_layers(krate: &Crate, prefix: &[&str], scope: &str, problems: &mut Vec<String>) {
    let layers = declared_layers(scope);
    let top = |path: &ModPath| -> Option<String> {
        (path.len() > prefix.len() && path.iter().zip(prefix).all(|(a, b)| a == b))
            .then(|| path[prefix.len()].clone())
    };
    for (module, _) in krate.files() {
        if let Some(name) = top(module)
            && !layers.contains_key(&name)
        {
            problems.push(format!(
                "{scope}: module `{name}` is in no layer of ARCHITECTURE.md"
            ));
        }
    }
    for (from, targets) in krate.edges() {
        let Some(a) = top(from) else { continue };
        for to in targets {
            let Some(b) = top(to) else { continue };
            if let (Some(la), Some(lb)) = (layers.get(&a), layers.get(&b))
                && lb > la
            {
                problems.push(format!(
                    "{scope}: `{}` ({}) imports `{}`, a layer above it",
                    shown(from),
                    krate.file_of(from).display(),
                    shown(to)
                ));
            }
        }
    }
}

#[test]
fn each_layer_imports_only_from_the_layers_below() {
    let crates = crates();
    let mut problems = Vec::new();
    check_layers(&crates[0].1, &[], "crates/pushlab-core/src", &mut problems);
    check_layers(
        &crates[1].1,
        &["app", "state"],
        "src/app/state",
        &mut problems,
    );
    check_layers(&crates[3].1, &[], "crates/pushlab-py/src", &mut problems);
    problems.sort();
    problems.dedup();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn no_source_file_is_over_600_lines() {
    let mut long = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    for (_, krate) in crates() {
        for (_, file) in krate.files() {
            if seen.iter().any(|f| f == file) {
                continue;
            }
            seen.push(file.to_path_buf());
            let text = std::fs::read_to_string(file).expect("readable");
            let lines = source::code_lines(&text);
            if lines > MAX_LINES {
                long.push(format!(
                    "{}: {lines} lines",
                    file.strip_prefix(root()).unwrap_or(file).display()
                ));
            }
        }
    }
    assert!(
        seen.len() > 100,
        "only {} files found: the module walk is broken",
        seen.len()
    );
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines of non-test code (split by concern):\n{}",
        long.join("\n")
    );
}
