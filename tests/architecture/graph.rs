//! The module graph of one crate, file by file: which module's code names which module's items.
//!
//! Modules are found by following `mod NAME;` from the crate's root file, as the compiler does (test
//! modules left out). An edge `a → b` means code in `a` names an item that `b` defines, following
//! re-exports to where the item is defined. A module's `pub use` of its own descendants is its
//! facade, not a dependency: `recording/mod.rs` re-exporting `native::read_set` does not make
//! `recording` depend on `native`.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::{Path, PathBuf};

use super::source::{code_paths, cut_test_modules, definitions, expand, strip, uses};

/// A module by its path from the crate root (`["recording", "bag"]`; the root is empty).
pub type ModPath = Vec<String>;

/// What one module's file says.
struct Module {
    file: PathBuf,
    /// Items it defines.
    defined: HashSet<String>,
    /// Items it re-exports, by name, with the path they come from.
    re_exported: HashMap<String, ModPath>,
    /// Paths named by its `use` statements (absolute), and whether each was a re-export.
    used: Vec<(bool, ModPath)>,
    /// Paths named in its code, as written.
    written: Vec<ModPath>,
    /// Names brought in by `use` (for paths written through them).
    imported: HashMap<String, ModPath>,
}

/// One crate's modules and the edges between them.
pub struct Crate {
    modules: BTreeMap<ModPath, Module>,
    edges: BTreeMap<ModPath, BTreeSet<ModPath>>,
}

impl Crate {
    /// The crate whose root file is `root` (`lib.rs` or `main.rs`).
    pub fn read(root: &Path) -> Self {
        let mut modules = BTreeMap::new();
        read_module(root, Vec::new(), true, &mut modules);
        let mut krate = Self {
            modules,
            edges: BTreeMap::new(),
        };
        krate.edges = krate.find_edges();
        krate
    }

    /// Every module with its file.
    pub fn files(&self) -> impl Iterator<Item = (&ModPath, &Path)> {
        self.modules
            .iter()
            .map(|(path, m)| (path, m.file.as_path()))
    }

    /// The edges, module to modules it depends on.
    pub fn edges(&self) -> &BTreeMap<ModPath, BTreeSet<ModPath>> {
        &self.edges
    }

    /// The file of a module, for messages.
    pub fn file_of(&self, module: &ModPath) -> &Path {
        &self.modules[module].file
    }

    fn find_edges(&self) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
        let mut edges: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
        for (path, module) in &self.modules {
            let mut targets = BTreeSet::new();
            for (public, used) in &module.used {
                let Some(target) = self.resolve(used) else {
                    continue;
                };
                // A re-export of one's own descendant is a facade.
                if *public && target.len() > path.len() && target.starts_with(path) {
                    continue;
                }
                targets.insert(target);
            }
            for written in &module.written {
                let base = match written[0].as_str() {
                    "crate" | "super" | "self" => absolute(path, written),
                    first => module
                        .imported
                        .get(first)
                        .filter(|m| self.modules.contains_key(*m))
                        .map(|m| [m.clone(), written[1..].to_vec()].concat())
                        .or_else(|| {
                            let child = [path.clone(), vec![first.to_owned()]].concat();
                            self.modules
                                .contains_key(&child)
                                .then(|| [path.clone(), written.clone()].concat())
                        }),
                };
                if let Some(target) = base.and_then(|b| self.resolve(&b)) {
                    targets.insert(target);
                }
            }
            targets.remove(path);
            edges.insert(path.clone(), targets);
        }
        edges
    }

    /// The module that defines the item at `path` (or the module `path` itself), following
    /// re-exports; `None` for paths outside the crate.
    fn resolve(&self, path: &ModPath) -> Option<ModPath> {
        self.resolve_at(path, 0)
    }

    fn resolve_at(&self, path: &ModPath, depth: usize) -> Option<ModPath> {
        if depth > 16 {
            return None;
        }
        let split = (0..=path.len())
            .rev()
            .find(|&k| self.modules.contains_key(&path[..k]))?;
        let (module, rest) = (path[..split].to_vec(), &path[split..]);
        let Some(name) = rest.first().filter(|n| n.as_str() != "*") else {
            return Some(module);
        };
        let m = &self.modules[&module];
        match m.re_exported.get(name) {
            Some(from) if !m.defined.contains(name) => {
                let onward = [from.clone(), rest[1..].to_vec()].concat();
                self.resolve_at(&onward, depth + 1).or(Some(module))
            }
            _ => Some(module),
        }
    }
}

/// Reads the module in `file` at `path` and the modules it declares, recursively.
fn read_module(
    file: &Path,
    path: ModPath,
    owns_directory: bool,
    modules: &mut BTreeMap<ModPath, Module>,
) {
    let text = std::fs::read_to_string(file)
        .unwrap_or_else(|e| panic!("{}: cannot read: {e}", file.display()));
    let (_, code) = cut_test_modules(&strip(&text));
    let dir = if owns_directory {
        file.parent().map(Path::to_path_buf).unwrap_or_default()
    } else {
        file.with_extension("")
    };
    for child in declared_modules(&code) {
        let candidates = [
            dir.join(format!("{child}.rs")),
            dir.join(&child).join("mod.rs"),
        ];
        if let Some(child_file) = candidates.iter().find(|p| p.is_file()) {
            let owns = child_file.ends_with("mod.rs");
            let child_path = [path.clone(), vec![child]].concat();
            read_module(child_file, child_path, owns, modules);
        }
    }
    let mut module = Module {
        file: file.to_path_buf(),
        defined: definitions(&code).into_iter().collect(),
        re_exported: HashMap::new(),
        used: Vec::new(),
        written: Vec::new(),
        imported: HashMap::new(),
    };
    for statement in uses(&code) {
        for written in statement.paths {
            let Some(target) = absolute(&path, &written).or_else(|| {
                // `use child::Item` names a child module without `self::`.
                let child = [path.clone(), vec![written[0].clone()]].concat();
                modules
                    .contains_key(&child)
                    .then(|| [path.clone(), written.clone()].concat())
            }) else {
                continue;
            };
            let name = match written.last().map(String::as_str) {
                Some("self") => written.get(written.len().wrapping_sub(2)).cloned(),
                other => other.map(str::to_owned),
            };
            let target = if written.last().map(String::as_str) == Some("self") {
                target[..target.len() - 1].to_vec()
            } else {
                target
            };
            if let Some(name) = name {
                if statement.public {
                    module.re_exported.insert(name.clone(), target.clone());
                }
                module.imported.insert(name, target.clone());
            }
            module.used.push((statement.public, target));
        }
    }
    let without_uses = remove_uses(&code);
    module.written = code_paths(&without_uses);
    modules.insert(path, module);
}

/// The names of `mod NAME;` declarations (not inline `mod NAME { … }`).
fn declared_modules(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut search = 0;
    while let Some(offset) = code[search..].find("mod ") {
        let at = search + offset;
        search = at + 4;
        if code[..at]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_')
        {
            continue;
        }
        let name: String = code[at + 4..]
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if code[at + 4 + name.len()..].trim_start().starts_with(';') {
            names.push(name);
        }
    }
    names
}

/// The text without its `use` statements.
fn remove_uses(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut rest = code;
    while let Some(at) = rest.find("use ") {
        let boundary = rest[..at]
            .chars()
            .next_back()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'));
        let end = rest[at..].find(';').map(|e| at + e + 1);
        match (boundary, end) {
            (true, Some(end)) => {
                out.push_str(&rest[..at]);
                rest = &rest[end..];
            }
            _ => {
                out.push_str(&rest[..at + 4]);
                rest = &rest[at + 4..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// `crate::`, `super::` and `self::` paths made absolute from `module`; `None` for others.
fn absolute(module: &ModPath, written: &[String]) -> Option<ModPath> {
    let mut base = module.clone();
    let mut rest = written;
    match rest.first().map(String::as_str) {
        Some("crate") => {
            base.clear();
            rest = &rest[1..];
        }
        Some("self") => rest = &rest[1..],
        Some("super") => {
            while rest.first().map(String::as_str) == Some("super") {
                base.pop()?;
                rest = &rest[1..];
            }
        }
        _ => return None,
    }
    Some([base, rest.to_vec()].concat())
}

/// Every cycle of an edge map: its strongly connected components of more than one module.
pub fn cycles(edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) -> Vec<Vec<ModPath>> {
    // Tarjan's algorithm, iteratively over an index of the nodes.
    let nodes: Vec<&ModPath> = edges
        .keys()
        .chain(edges.values().flatten())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let id: HashMap<&ModPath, usize> = nodes.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let next: Vec<Vec<usize>> = nodes
        .iter()
        .map(|n| edges.get(*n).into_iter().flatten().map(|m| id[m]).collect())
        .collect();
    let n = nodes.len();
    let (mut index, mut low, mut on_stack) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut components, mut counter) = (Vec::new(), Vec::new(), 0);
    for start in 0..n {
        if index[start] != usize::MAX {
            continue;
        }
        let mut work = vec![(start, 0usize)];
        while let Some(&mut (v, ref mut child)) = work.last_mut() {
            if *child == 0 {
                index[v] = counter;
                low[v] = counter;
                counter += 1;
                stack.push(v);
                on_stack[v] = true;
            }
            if let Some(&w) = next[v].get(*child) {
                *child += 1;
                if index[w] == usize::MAX {
                    work.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                let mut component = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w] = false;
                    component.push(nodes[w].clone());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    components.push(component);
                }
            }
        }
    }
    components
}

/// A `use` tree's paths, for tests of this module.
#[cfg(test)]
pub fn expanded(tree: &str) -> Vec<ModPath> {
    expand(tree, &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edges(list: &[(&str, &str)]) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
        let mut map: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
        for (a, b) in list {
            map.entry(vec![a.to_string()])
                .or_default()
                .insert(vec![b.to_string()]);
        }
        map
    }

    #[test]
    fn a_loop_is_a_cycle_and_a_chain_is_not() {
        assert!(cycles(&edges(&[("a", "b"), ("b", "c")])).is_empty());
        let found = cycles(&edges(&[("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]));
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].len(), 3);
    }

    #[test]
    fn paths_are_made_absolute() {
        let module = vec!["a".to_owned(), "b".to_owned()];
        let path = |p: &[&str]| p.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert_eq!(
            absolute(&module, &path(&["super", "c"])),
            Some(path(&["a", "c"]))
        );
        assert_eq!(
            absolute(&module, &path(&["crate", "x"])),
            Some(path(&["x"]))
        );
        assert_eq!(
            absolute(&module, &path(&["self", "y"])),
            Some(path(&["a", "b", "y"]))
        );
        assert_eq!(absolute(&module, &path(&["std", "y"])), None);
        assert_eq!(expanded("a::{b, c}").len(), 2);
    }
}
