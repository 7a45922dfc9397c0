//! Just enough markdown for checking links: where the links are (outside code), and the
//! anchors a file's headings get on GitHub and in mdBook 0.5.

use std::collections::HashSet;

/// Which renderer's heading ids a markdown file gets: mdBook (its smart punctuation turns `--`
/// into a dash, which the id drops) for guide pages, GitHub for the rest.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Flavour {
    GitHub,
    MdBook,
}

/// A link's destination and the 1-based line it is on.
#[derive(Debug, PartialEq)]
pub(super) struct Link {
    pub(super) line: usize,
    pub(super) dest: String,
}

/// The destinations of every inline link and image (`[text](dest)`, `![alt](dest "title")`),
/// reference definition (`[label]: dest`) and full or collapsed reference (`[text][label]`, whose
/// label must be defined) outside code; a reference without a definition is returned as the
/// destination `[label` (no real destination starts with `[`). The line is that of the destination.
pub(super) fn links(text: &str) -> Vec<Link> {
    let masked = mask_code(text);
    let chars: Vec<char> = masked.chars().collect();
    let line_at = |index: usize| 1 + chars[..index].iter().filter(|&&c| c == '\n').count();
    let mut found = Vec::new();
    let mut definitions = HashSet::new();
    for (number, line) in masked.lines().enumerate() {
        if let Some((label, dest)) = reference_definition(line) {
            definitions.insert(label);
            found.push(Link {
                line: number + 1,
                dest,
            });
        }
    }
    let mut index = 0;
    while index + 1 < chars.len() {
        if chars[index] != ']' || opening_bracket(&chars, index).is_none() {
            index += 1;
            continue;
        }
        match chars[index + 1] {
            '(' => {
                let (dest, end) = inline_destination(&chars, index + 2);
                found.push(Link {
                    line: line_at(index + 1),
                    dest,
                });
                index = end;
            }
            '[' => {
                let Some(close) = chars[index + 2..].iter().position(|&c| c == ']') else {
                    index += 1;
                    continue;
                };
                let mut label: String = chars[index + 2..index + 2 + close].iter().collect();
                if label.is_empty() {
                    // A collapsed reference, `[text][]`: the text is the label.
                    let open = opening_bracket(&chars, index).unwrap_or(index);
                    label = chars[open + 1..index].iter().collect();
                }
                if !definitions.contains(&normalize_label(&label)) {
                    found.push(Link {
                        line: line_at(index + 1),
                        dest: format!("[{label}"),
                    });
                }
                index += close + 3;
            }
            _ => index += 1,
        }
    }
    found.sort_by_key(|link| link.line);
    found
}

/// The `[` that a `]` at `close` closes, brackets balanced, within the paragraph.
fn opening_bracket(chars: &[char], close: usize) -> Option<usize> {
    let mut depth = 0;
    for index in (0..close).rev() {
        match chars[index] {
            ']' => depth += 1,
            '[' if depth == 0 => return Some(index),
            '[' => depth -= 1,
            '\n' if index > 0 && chars[index - 1] == '\n' => return None,
            _ => {}
        }
    }
    None
}

/// The destination of an inline link starting at `start` (after `](`), and where the link ends.
fn inline_destination(chars: &[char], start: usize) -> (String, usize) {
    let mut index = start;
    while index < chars.len() && chars[index].is_whitespace() {
        index += 1;
    }
    let mut dest = String::new();
    if chars.get(index) == Some(&'<') {
        index += 1;
        while index < chars.len() && chars[index] != '>' && chars[index] != '\n' {
            dest.push(chars[index]);
            index += 1;
        }
        return (dest, index);
    }
    let mut depth = 0;
    while index < chars.len() && !chars[index].is_whitespace() {
        match chars[index] {
            '(' => depth += 1,
            ')' if depth == 0 => break,
            ')' => depth -= 1,
            _ => {}
        }
        dest.push(chars[index]);
        index += 1;
    }
    (dest, index)
}

/// `[label]: dest` at the start of a line (up to three spaces in): the normalised label and dest.
fn reference_definition(line: &str) -> Option<(String, String)> {
    let indent = line.len() - line.trim_start_matches(' ').len();
    let rest = line.trim_start_matches(' ').strip_prefix('[')?;
    if indent > 3 {
        return None;
    }
    let (label, rest) = rest.split_once("]:")?;
    let dest = rest.split_whitespace().next()?;
    let dest = dest
        .strip_prefix('<')
        .and_then(|d| d.strip_suffix('>'))
        .unwrap_or(dest);
    Some((normalize_label(label), dest.to_owned()))
}

/// Reference labels match case-insensitively, with runs of whitespace as one space.
fn normalize_label(label: &str) -> String {
    label
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

/// `text` with code blocks, inline code, HTML comments and backslash-escaped characters blanked out
/// (each character a space, newlines kept), so that links in them are not seen and lines still count.
fn mask_code(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut fence: Option<(char, usize)> = None;
    let mut paragraph = String::new();
    for line in text.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if let Some((fence_char, fence_len)) = fence {
            let run = trimmed.chars().take_while(|&c| c == fence_char).count();
            if run >= fence_len && trimmed[run * fence_char.len_utf8()..].trim().is_empty() {
                fence = None;
            }
            out.push_str(&blank(line));
            continue;
        }
        let opening = ['`', '~'].into_iter().find_map(|c| {
            let run = trimmed.chars().take_while(|&x| x == c).count();
            (run >= 3).then_some((c, run))
        });
        if opening.is_some() {
            out.push_str(&mask_inline(&paragraph));
            paragraph.clear();
            fence = opening;
            out.push_str(&blank(line));
            continue;
        }
        paragraph.push_str(line);
        if line.trim().is_empty() {
            out.push_str(&mask_inline(&paragraph));
            paragraph.clear();
        }
    }
    out.push_str(&mask_inline(&paragraph));
    out
}

/// Every character but newlines as a space.
fn blank(text: &str) -> String {
    text.chars()
        .map(|c| if c == '\n' { '\n' } else { ' ' })
        .collect()
}

/// One paragraph with its code spans, HTML comments and escaped characters blanked.
fn mask_inline(paragraph: &str) -> String {
    let chars: Vec<char> = paragraph.chars().collect();
    let mut out = String::with_capacity(paragraph.len());
    let mut index = 0;
    while index < chars.len() {
        let c = chars[index];
        if c == '\\'
            && chars
                .get(index + 1)
                .is_some_and(|n| n.is_ascii_punctuation())
        {
            out.push_str("  ");
            index += 2;
        } else if c == '`' {
            let run = chars[index..].iter().take_while(|&&x| x == '`').count();
            match closing_backticks(&chars, index + run, run) {
                Some(end) => {
                    out.push_str(&blank(&chars[index..end].iter().collect::<String>()));
                    index = end;
                }
                None => {
                    out.extend(std::iter::repeat_n('`', run));
                    index += run;
                }
            }
        } else if chars[index..].starts_with(&['<', '!', '-', '-']) {
            let rest: String = chars[index..].iter().collect();
            let end = rest.find("-->").map_or(rest.len(), |at| at + 3);
            out.push_str(&blank(&rest[..end]));
            index += rest[..end].chars().count();
        } else {
            out.push(c);
            index += 1;
        }
    }
    out
}

/// The index just after the run of exactly `run` backticks that closes a code span from `from`.
fn closing_backticks(chars: &[char], from: usize, run: usize) -> Option<usize> {
    let mut index = from;
    while index < chars.len() {
        if chars[index] == '`' {
            let length = chars[index..].iter().take_while(|&&x| x == '`').count();
            if length == run {
                return Some(index + length);
            }
            index += length;
        } else {
            index += 1;
        }
    }
    None
}

/// The anchors of a markdown file's headings (ATX `#` and setext `===`/`---`), outside code blocks:
/// each heading's [`heading_id`], or its `{#id}` attribute; a repeated id gets `-1`, `-2`, ….
pub(super) fn heading_ids(text: &str, flavour: Flavour) -> HashSet<String> {
    let masked = mask_code(text);
    let source: Vec<&str> = text.lines().collect();
    let masked: Vec<&str> = masked.lines().collect();
    let mut ids = HashSet::new();
    let mut paragraph: Vec<&str> = Vec::new();
    for (index, line) in masked.iter().enumerate() {
        let original = source.get(index).copied().unwrap_or_default();
        let heading = if line.trim().is_empty() {
            paragraph.clear();
            None
        } else if let Some(text) = atx_heading(original).filter(|_| !line.trim().is_empty()) {
            paragraph.clear();
            Some(text.to_owned())
        } else if is_setext_underline(line) && !paragraph.is_empty() {
            let text = paragraph.join(" ");
            paragraph.clear();
            Some(text)
        } else {
            if starts_paragraph_text(line) || !paragraph.is_empty() {
                paragraph.push(original);
            }
            None
        };
        if let Some(heading) = heading {
            let id = explicit_id(&heading).unwrap_or_else(|| heading_id(&heading, flavour));
            let mut unique = id.clone();
            let mut counter = 1;
            while !ids.insert(unique.clone()) {
                unique = format!("{id}-{counter}");
                counter += 1;
            }
        }
    }
    ids
}

/// The text of an ATX heading (`## Text ##`), up to three spaces in.
fn atx_heading(line: &str) -> Option<&str> {
    let trimmed = line.trim_start_matches(' ');
    if line.len() - trimmed.len() > 3 {
        return None;
    }
    let level = trimmed.chars().take_while(|&c| c == '#').count();
    if !(1..=6).contains(&level) {
        return None;
    }
    let rest = &trimmed[level..];
    if !rest.is_empty() && !rest.starts_with([' ', '\t']) {
        return None;
    }
    let rest = rest.trim();
    // A closing run of `#` preceded by a space is not part of the text.
    let without_closing = rest.trim_end_matches('#');
    if without_closing.is_empty() || without_closing.ends_with([' ', '\t']) {
        return Some(without_closing.trim_end());
    }
    Some(rest)
}

/// `===` or `---` (nothing else on the line), which makes the paragraph above a heading.
fn is_setext_underline(line: &str) -> bool {
    let trimmed = line.trim();
    let indent = line.len() - line.trim_start_matches(' ').len();
    indent <= 3
        && !trimmed.is_empty()
        && (trimmed.chars().all(|c| c == '=') || trimmed.chars().all(|c| c == '-'))
}

/// Whether a line can begin a paragraph (not a list item, quote, table row or HTML block).
fn starts_paragraph_text(line: &str) -> bool {
    let trimmed = line.trim_start();
    let ordered = trimmed.split_once(['.', ')']).is_some_and(|(number, _)| {
        !number.is_empty() && number.chars().all(|c| c.is_ascii_digit())
    });
    !(trimmed.starts_with(['-', '*', '+', '>', '|', '<']) || ordered)
}

/// The id of a heading's `{#id .class}` attribute block, which mdBook uses instead of the text.
fn explicit_id(heading: &str) -> Option<String> {
    let inner = heading.trim_end().strip_suffix('}')?;
    let attributes = &inner[inner.rfind('{')? + 1..];
    attributes
        .split_whitespace()
        .find_map(|attribute| attribute.strip_prefix('#'))
        .map(str::to_owned)
}

/// The anchor of a heading, from its markdown source: the text as rendered (code spans' content,
/// links' text; emphasis, images, HTML tags and escapes dropped), then mdBook 0.5's
/// `id_from_content`, which is GitHub's rule too: trimmed, lowercased, letters, digits, `_` and `-`
/// kept, whitespace turned into `-`, everything else dropped. mdBook's smart punctuation turns `--`
/// outside code into a dash, which is dropped.
fn heading_id(heading: &str, flavour: Flavour) -> String {
    rendered_text(heading, flavour)
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                Some(c)
            } else if c.is_whitespace() {
                Some('-')
            } else {
                None
            }
        })
        .collect()
}

/// The plain text a heading's inline markdown renders to, as far as ids care.
fn rendered_text(source: &str, flavour: Flavour) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::new();
    let mut index = 0;
    while index < chars.len() {
        let c = chars[index];
        match c {
            '\\' if chars
                .get(index + 1)
                .is_some_and(|n| n.is_ascii_punctuation()) =>
            {
                out.push(chars[index + 1]);
                index += 2;
            }
            '`' => {
                let run = chars[index..].iter().take_while(|&&x| x == '`').count();
                if let Some(end) = closing_backticks(&chars, index + run, run) {
                    let code: String = chars[index + run..end - run].iter().collect();
                    // One space on both sides of a code span's content is padding.
                    let code = match code.strip_prefix(' ').and_then(|c| c.strip_suffix(' ')) {
                        Some(inner) if !inner.trim().is_empty() => inner.to_owned(),
                        _ => code,
                    };
                    out.push_str(&code);
                    index = end;
                } else {
                    out.extend(std::iter::repeat_n('`', run));
                    index += run;
                }
            }
            '!' if chars.get(index + 1) == Some(&'[') => {
                // An image: its alt text is an attribute, not text.
                let close = chars[index..].iter().position(|&x| x == ']');
                let end = close.map_or(chars.len(), |close| {
                    let after = index + close + 1;
                    if chars.get(after) == Some(&'(') {
                        inline_destination(&chars, after + 1).1 + 1
                    } else {
                        after
                    }
                });
                index = end.min(chars.len());
            }
            ']' if chars.get(index + 1) == Some(&'(') => {
                // The end of a link's text: skip its destination.
                index = (inline_destination(&chars, index + 2).1 + 1).min(chars.len());
            }
            '[' | ']' | '*' | '~' => index += 1,
            '_' => {
                let run = chars[index..].iter().take_while(|&&x| x == '_').count();
                let before = index.checked_sub(1).map(|i| chars[i]);
                let after = chars.get(index + run).copied();
                // Inside a word `_` is text; at a word's edge it is emphasis.
                if before.is_some_and(char::is_alphanumeric)
                    && after.is_some_and(char::is_alphanumeric)
                {
                    out.extend(std::iter::repeat_n('_', run));
                }
                index += run;
            }
            '-' if flavour == Flavour::MdBook && chars.get(index + 1) == Some(&'-') => {
                index += chars[index..].iter().take_while(|&&x| x == '-').count();
            }
            '<' => {
                let end = chars[index..].iter().position(|&x| x == '>');
                match end {
                    Some(end) => index += end + 1,
                    None => {
                        out.push(c);
                        index += 1;
                    }
                }
            }
            '&' => {
                let entity: String = chars[index..].iter().take(10).collect();
                match entity.find(';') {
                    Some(end)
                        if entity[1..end]
                            .chars()
                            .all(|x| x.is_ascii_alphanumeric() || x == '#') =>
                    {
                        if &entity[..=end] == "&nbsp;" {
                            out.push(' ');
                        }
                        index += end + 1;
                    }
                    _ => {
                        out.push(c);
                        index += 1;
                    }
                }
            }
            _ => {
                out.push(c);
                index += 1;
            }
        }
    }
    out
}

#[test]
fn links_in_code_are_not_checked_and_references_are() {
    let text = "Inline `[x](nowhere.md)` and ``[y](` nowhere `)`` code.\n\
                \n\
                ```sh\n\
                echo [z](nowhere.md)\n\
                ```\n\
                \n\
                <!-- [hidden](nowhere.md) -->\n\
                A [reference][ref], a [collapsed][] one and an [undefined][nope].\n\
                \n\
                [ref]: target.md#part\n\
                [Collapsed]: other.md\n";
    assert_eq!(
        links(text),
        vec![
            Link {
                line: 8,
                dest: "[nope".to_owned()
            },
            Link {
                line: 10,
                dest: "target.md#part".to_owned()
            },
            Link {
                line: 11,
                dest: "other.md".to_owned()
            },
        ]
    );
}

#[test]
fn anchors_follow_the_github_and_mdbook_rule() {
    let id = |heading| heading_id(heading, Flavour::GitHub);
    assert_eq!(
        id("The model (`crates/pushlab-core`)"),
        "the-model-cratespushlab-core"
    );
    assert_eq!(
        id("Experiments: `pushlab train`, `pushlab eval` and `pushlab suite`"),
        "experiments-pushlab-train-pushlab-eval-and-pushlab-suite"
    );
    assert_eq!(
        id("Uncertainty: how sure is the COM estimate, and a faster optimiser"),
        "uncertainty-how-sure-is-the-com-estimate-and-a-faster-optimiser"
    );
    assert_eq!(
        id("Where the `paper` kind *departs*"),
        "where-the-paper-kind-departs"
    );
    assert_eq!(id("`θ_online` and _emphasis_"), "θ_online-and-emphasis");
    assert_eq!(
        id("A [link](x.md) and ![img](y.png) here"),
        "a-link-and--here"
    );
    assert_eq!(id("Über 中文 & co."), "über-中文--co");
    assert_eq!(id("Options `--rate` -- here"), "options---rate----here");
    assert_eq!(
        heading_id("Options `--rate` -- here", Flavour::MdBook),
        "options---rate--here"
    );

    let ids = heading_ids(
        "# Intro\n\n## Intro\n\n## Intro ##\n\nSetext heading\n---\n\n```\n# not a heading\n```\n\n## Custom {#my-id}\n",
        Flavour::MdBook,
    );
    let expected: HashSet<String> = ["intro", "intro-1", "intro-2", "setext-heading", "my-id"]
        .into_iter()
        .map(str::to_owned)
        .collect();
    assert_eq!(ids, expected);
}
