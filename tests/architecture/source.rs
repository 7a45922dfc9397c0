//! Reading Rust sources as the architecture checks need them: comments, strings and character
//! literals blanked out, test modules cut, `use` trees expanded into paths. Not a Rust parser — just
//! enough of one for module paths, which is all these checks read.

/// The text with comments removed and string and character literals emptied, so that nothing inside
/// them looks like a path. Lifetimes (`'a`) are kept.
pub fn strip(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let starts = |i: usize, s: &str| {
        s.chars()
            .enumerate()
            .all(|(k, c)| chars.get(i + k) == Some(&c))
    };
    while i < chars.len() {
        let c = chars[i];
        if starts(i, "//") {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if starts(i, "/*") {
            let mut depth = 0;
            while i < chars.len() {
                if starts(i, "/*") {
                    depth += 1;
                    i += 2;
                } else if starts(i, "*/") {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if let Some(end) = raw_string_end(&chars, i) {
            out.push_str("\"\"");
            i = end;
        } else if c == '"' {
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += if chars[i] == '\\' { 2 } else { 1 };
            }
            out.push_str("\"\"");
            i += 1;
        } else if let Some(end) = char_literal_end(&chars, i) {
            out.push_str("' '");
            i = end;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// Where a raw string (`r"…"`, `r#"…"#`, `br"…"`) starting at `i` ends, if one starts there.
fn raw_string_end(chars: &[char], i: usize) -> Option<usize> {
    if i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_') {
        return None;
    }
    let mut k = i;
    if chars.get(k) == Some(&'b') {
        k += 1;
    }
    if chars.get(k) != Some(&'r') {
        return None;
    }
    k += 1;
    let hashes = chars[k..].iter().take_while(|&&c| c == '#').count();
    k += hashes;
    if chars.get(k) != Some(&'"') {
        return None;
    }
    k += 1;
    while k < chars.len() {
        if chars[k] == '"'
            && chars[k + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == '#')
                .count()
                == hashes
        {
            return Some(k + 1 + hashes);
        }
        k += 1;
    }
    Some(chars.len())
}

/// Where a character literal (`'x'`, `'\n'`, `'\u{1F600}'`) starting at `i` ends, if one starts there
/// (a lifetime `'a` is not one).
fn char_literal_end(chars: &[char], i: usize) -> Option<usize> {
    if chars.get(i) != Some(&'\'') {
        return None;
    }
    if chars.get(i + 1) == Some(&'\\') {
        let close = (i + 2..chars.len().min(i + 14)).find(|&k| chars[k] == '\'')?;
        return Some(close + 1);
    }
    (chars.get(i + 2) == Some(&'\'')).then_some(i + 3)
}

/// The names of the modules declared `#[cfg(test)] mod NAME;` (in their own file), and the text
/// without the `#[cfg(test)] mod NAME { … }` blocks written inline.
pub fn cut_test_modules(text: &str) -> (Vec<String>, String) {
    const ATTRIBUTE: &str = "#[cfg(test)]";
    let mut names = Vec::new();
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(ATTRIBUTE) {
        out.push_str(&rest[..at]);
        let after = &rest[at + ATTRIBUTE.len()..];
        let trimmed = after.trim_start();
        // Any visibility: `pub`, `pub(crate)`, `pub(super)`, `pub(in path)`.
        let trimmed = match trimmed.strip_prefix("pub(") {
            Some(inside) => inside
                .split_once(')')
                .map_or(trimmed, |(_, rest)| rest.trim_start()),
            None => trimmed,
        };
        let declaration = ["pub mod ", "mod "]
            .iter()
            .find_map(|keyword| trimmed.strip_prefix(keyword));
        let Some(declaration) = declaration else {
            // A test-only item other than a module: kept, its attribute too.
            out.push_str(ATTRIBUTE);
            rest = after;
            continue;
        };
        let name: String = declaration
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let tail = declaration[name.len()..].trim_start();
        if let Some(after_semicolon) = tail.strip_prefix(';') {
            names.push(name);
            rest = after_semicolon;
            continue;
        }
        let mut depth = 0usize;
        let mut end = tail.len();
        for (k, c) in tail.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        end = k + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        rest = &tail[end..];
    }
    out.push_str(rest);
    (names, out)
}

/// One `use` statement: whether it re-exports (`pub use`, `pub(crate) use`) and its paths.
#[derive(Debug, PartialEq)]
pub struct Use {
    pub public: bool,
    pub paths: Vec<Vec<String>>,
}

/// Every `use` statement of stripped text.
pub fn uses(text: &str) -> Vec<Use> {
    let mut found = Vec::new();
    let bytes = text.as_bytes();
    let mut search = 0;
    while let Some(offset) = text[search..].find("use ") {
        let at = search + offset;
        search = at + 4;
        if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
            continue;
        }
        let Some(end) = text[at..].find(';') else {
            break;
        };
        let tree = &text[at + 4..at + end];
        let before = text[..at].trim_end();
        let public = before.ends_with("pub") || before.ends_with(')') && before.contains("pub(");
        found.push(Use {
            public: public && is_visibility_before(before),
            paths: expand(tree, &[]),
        });
        search = at + end;
    }
    found
}

/// Whether the text just before a `use` ends with a visibility (`pub`, `pub(crate)`, `pub(super)`).
fn is_visibility_before(before: &str) -> bool {
    if before.ends_with("pub") {
        return true;
    }
    before
        .rfind("pub(")
        .is_some_and(|k| before[k..].ends_with(')') && !before[k..].contains('\n'))
}

/// The paths of a `use` tree, such as `a::{b, c::{d, e as f}}`.
pub fn expand(tree: &str, prefix: &[String]) -> Vec<Vec<String>> {
    let tree = tree.trim();
    if let Some(open) = tree.find('{') {
        let head: Vec<String> = segments(&tree[..open]);
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let mut prefix = prefix.to_vec();
        prefix.extend(head);
        let mut parts = Vec::new();
        let (mut depth, mut start) = (0, 0);
        for (k, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    parts.push(&inner[start..k]);
                    start = k + 1;
                }
                _ => {}
            }
        }
        parts.push(&inner[start..]);
        return parts
            .into_iter()
            .filter(|p| !p.trim().is_empty())
            .flat_map(|p| expand(p, &prefix))
            .collect();
    }
    let tree = tree.split(" as ").next().unwrap_or(tree);
    let mut path = prefix.to_vec();
    path.extend(segments(tree));
    vec![path]
}

fn segments(text: &str) -> Vec<String> {
    text.split("::")
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(str::to_owned)
        .collect()
}

/// The paths written in code (not in `use`): `crate::a::b`, `super::a`, `self::a`, or `name::a`
/// for any `name` (the caller decides which names are modules).
pub fn code_paths(text: &str) -> Vec<Vec<String>> {
    let mut paths = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut i = 0;
    while i < chars.len() {
        if !is_ident(chars[i]) || (i > 0 && (is_ident(chars[i - 1]) || chars[i - 1] == ':')) {
            i += 1;
            continue;
        }
        let mut path = Vec::new();
        let mut k = i;
        loop {
            let start = k;
            while k < chars.len() && is_ident(chars[k]) {
                k += 1;
            }
            if start == k {
                break;
            }
            path.push(chars[start..k].iter().collect::<String>());
            if chars.get(k) == Some(&':') && chars.get(k + 1) == Some(&':') {
                k += 2;
            } else {
                break;
            }
        }
        // A visibility's path (`pub(in crate::app::state)`) says who may see an item, not what it
        // uses.
        let before: String = chars[i.saturating_sub(8)..i].iter().collect();
        if path.len() > 1 && !before.trim_end().ends_with("(in") {
            paths.push(path);
        }
        i = k.max(i + 1);
    }
    paths
}

/// The names of the items a module defines itself.
pub fn definitions(text: &str) -> Vec<String> {
    let mut names = Vec::new();
    for keyword in [
        "struct ",
        "enum ",
        "fn ",
        "trait ",
        "type ",
        "const ",
        "static ",
        "union ",
        "mod ",
        "macro_rules! ",
    ] {
        let mut search = 0;
        while let Some(offset) = text[search..].find(keyword) {
            let at = search + offset;
            search = at + keyword.len();
            let before = text[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let name: String = text[at + keyword.len()..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                names.push(name);
            }
        }
    }
    names
}

/// Lines of non-test code in a file: up to its inline `#[cfg(test)] mod tests` block (test modules
/// stand last in this code base), all of it for a file without one.
pub fn code_lines(text: &str) -> usize {
    let at = [
        "#[cfg(test)]\nmod tests {",
        "#[cfg(test)]\npub(crate) mod tests {",
    ]
    .iter()
    .filter_map(|marker| text.find(marker))
    .min();
    let code = at.map_or(text, |at| &text[..at]);
    code.lines().count()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_comments_and_chars_hide_nothing_and_lifetimes_stay() {
        let text = "let a = \"crate::x\"; // super::y\n/* self::z */ let c = '\\''; fn f<'a>() {} r#\"crate::w\"#";
        let stripped = strip(text);
        assert!(!stripped.contains("crate::x") && !stripped.contains("super::y"));
        assert!(!stripped.contains("self::z") && !stripped.contains("crate::w"));
        assert!(stripped.contains("f<'a>"), "{stripped}");
    }

    #[test]
    fn use_trees_expand_and_re_exports_are_told_apart() {
        let found =
            uses("use a::{b, c::{d, e as f}};\npub use self::g::H;\npub(crate) use super::k;");
        assert_eq!(found.len(), 3);
        assert_eq!(
            found[0].paths,
            [vec!["a", "b"], vec!["a", "c", "d"], vec!["a", "c", "e"]]
        );
        assert!(!found[0].public && found[1].public && found[2].public);
    }

    #[test]
    fn test_modules_are_cut_and_named() {
        let (names, rest) = cut_test_modules(
            "fn a() {}\n#[cfg(test)]\nmod tests;\n#[cfg(test)]\nmod inline { use crate::x; }\nfn b() {}",
        );
        assert_eq!(names, ["tests"]);
        assert!(!rest.contains("crate::x") && rest.contains("fn b()"));
        let (names, _) = cut_test_modules("#[cfg(test)]\npub(in crate::app::state) mod tests;");
        assert_eq!(names, ["tests"], "a test module of any visibility");
    }

    #[test]
    fn a_visibilitys_path_is_not_a_use() {
        let paths = code_paths("pub(in crate::app::state) fn f() { crate::a::b(); }");
        assert_eq!(paths, [vec!["crate", "a", "b"]]);
    }
}
