//! A suite's results as a paper needs them (`pushlab suite --markdown OUT.md --latex OUT.tex`): the
//! terminal table's rows and columns — per model offline, fixed and online NMSE, then the
//! physics-only model's fixed and online, and the experiment's first model weighed with it online — as a Markdown table and as a LaTeX `booktabs` tabular.
//! In each row the lowest online position and rotation NMSE (over the models and physics online)
//! are set in bold; a number that could not be computed is a dash, and the experiment's errors are
//! listed under the table.

use pushlab_core::experiment::suite::{ExperimentResult, SuiteSpec};
use pushlab_core::learn::Nmse;

/// A way to write the table.
pub type Table = fn(&SuiteSpec, &[ExperimentResult]) -> String;

/// One cell: a pair of NMSE, each marked when it is the row's best online one.
struct Cell {
    nmse: Option<Nmse>,
    best: [bool; 2],
}

/// The cells of one experiment's row, in the columns' order, and whether each is an online one.
fn row(spec: &SuiteSpec, r: &ExperimentResult) -> Vec<Cell> {
    let mut cells: Vec<(Option<Nmse>, bool)> = Vec::new();
    for model in &spec.models {
        let k = r.models.iter().find(|k| k.model == *model);
        cells.push((k.map(|k| k.offline), false));
        cells.push((k.map(|k| k.fixed), false));
        cells.push((k.map(|k| k.online), true));
    }
    if spec.physics {
        let p = r.physics.as_ref();
        cells.push((p.map(|p| p.fixed), false));
        cells.push((p.map(|p| p.online), true));
        cells.push((p.and_then(|p| p.weighted), true));
    }
    let lowest = |part: fn(&Nmse) -> f64| {
        (cells.iter())
            .filter(|(n, online)| *online && n.is_some())
            .filter_map(|(n, _)| n.as_ref().map(part))
            .filter(|v| v.is_finite())
            .fold(f64::INFINITY, f64::min)
    };
    let best = [lowest(|n| n.pos), lowest(|n| n.rot)];
    // Bold only where there is a choice: two online columns or more.
    let choice = cells.iter().filter(|(_, online)| *online).count() > 1;
    cells
        .into_iter()
        .map(|(nmse, online)| Cell {
            best: [
                choice && online && nmse.is_some_and(|n| n.pos == best[0]),
                choice && online && nmse.is_some_and(|n| n.rot == best[1]),
            ],
            nmse,
        })
        .collect()
}

/// A row's cells as text, `position / rotation` to three decimals, the best ones wrapped by `bold`,
/// `dash` where a number could not be computed: the one cell rule of both tables.
fn cell_texts(
    spec: &SuiteSpec,
    r: &ExperimentResult,
    bold: fn(&str) -> String,
    dash: &str,
) -> Vec<String> {
    let number = |v: f64, best: bool| {
        let text = format!("{v:.3}");
        if best { bold(&text) } else { text }
    };
    (row(spec, r).iter())
        .map(|c| match c.nmse {
            Some(n) => format!(
                "{} / {}",
                number(n.pos, c.best[0]),
                number(n.rot, c.best[1])
            ),
            None => dash.to_owned(),
        })
        .collect()
}

/// The column groups: each model's name, then "physics only".
fn groups(spec: &SuiteSpec) -> Vec<(String, &'static [&'static str])> {
    let mut groups: Vec<(String, &'static [&'static str])> = (spec.models.iter())
        .map(|m| (m.name().to_owned(), &["offline", "fixed", "online"][..]))
        .collect();
    if spec.physics {
        groups.push(("physics only".to_owned(), &["fixed", "online"][..]));
        // Each experiment's first model and physics alone weighed online (`learn::ModelWeight`).
        groups.push(("weighted".to_owned(), &["online"][..]));
    }
    groups
}

/// The results as a Markdown table (GitHub's pipe tables).
pub fn markdown(spec: &SuiteSpec, results: &[ExperimentResult]) -> String {
    let mut header = vec!["Experiment".to_owned()];
    for (group, columns) in groups(spec) {
        header.extend(columns.iter().map(|c| format!("{group} {c}")));
    }
    let mut text = format!("| {} |\n", header.join(" | "));
    text += &format!(
        "|{}\n",
        header
            .iter()
            .enumerate()
            .map(|(i, _)| if i == 0 { " --- |" } else { " ---: |" })
            .collect::<String>()
    );
    for r in results {
        let cells = cell_texts(spec, r, |v| format!("**{v}**"), "–");
        text += &format!(
            "| {} | {} |\n",
            r.name.replace('|', "\\|"),
            cells.join(" | ")
        );
    }
    text += "\nNMSE of the predicted object motion, position / rotation (lower is better); the lowest online numbers of each row in bold.\n";
    for r in results.iter().filter(|r| !r.errors.is_empty()) {
        text += &format!("\n- {}: {}", r.name, r.errors.join("; "));
    }
    if results.iter().any(|r| !r.errors.is_empty()) {
        text.push('\n');
    }
    text
}

/// Text set in LaTeX with its special characters escaped.
fn latex_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' | '%' | '$' | '#' | '_' | '{' | '}' => {
                out.push('\\');
                out.push(c);
            }
            '~' => out.push_str("\\textasciitilde{}"),
            '^' => out.push_str("\\textasciicircum{}"),
            '\\' => out.push_str("\\textbackslash{}"),
            '–' => out.push_str("--"),
            _ => out.push(c),
        }
    }
    out
}

/// The results as a LaTeX `tabular` with `booktabs` rules (the document needs
/// `\usepackage{booktabs}`).
pub fn latex(spec: &SuiteSpec, results: &[ExperimentResult]) -> String {
    let groups = groups(spec);
    let columns: usize = groups.iter().map(|(_, c)| c.len()).sum();
    let mut text = String::from(
        "% pushlab suite: NMSE of the predicted object motion, position / rotation (lower is better);\n\
         % the lowest online numbers of each row in bold. Needs \\usepackage{booktabs}.\n",
    );
    text += &format!(
        "\\begin{{tabular}}{{l{}}}\n\\toprule\n",
        "c".repeat(columns)
    );
    let (mut spans, mut rules, mut first) = (Vec::new(), Vec::new(), 2);
    for (group, cols) in &groups {
        spans.push(format!(
            "\\multicolumn{{{}}}{{c}}{{{}}}",
            cols.len(),
            latex_text(group)
        ));
        rules.push(format!(
            "\\cmidrule(lr){{{first}-{}}}",
            first + cols.len() - 1
        ));
        first += cols.len();
    }
    text += &format!(" & {} \\\\\n{}\n", spans.join(" & "), rules.join(" "));
    let names: Vec<String> = (groups.iter())
        .flat_map(|(_, cols)| cols.iter().map(|c| capitalised(c)))
        .collect();
    text += &format!("Experiment & {} \\\\\n\\midrule\n", names.join(" & "));
    for r in results {
        let cells = cell_texts(spec, r, |v| format!("\\textbf{{{v}}}"), "--");
        text += &format!("{} & {} \\\\\n", latex_text(&r.name), cells.join(" & "));
    }
    text += "\\bottomrule\n\\end{tabular}\n";
    for r in results.iter().filter(|r| !r.errors.is_empty()) {
        text += &format!("% {}: {}\n", r.name, r.errors.join("; ").replace('\n', " "));
    }
    text
}

fn capitalised(word: &str) -> String {
    let mut chars = word.chars();
    chars
        .next()
        .map(|c| c.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latex_specials_are_escaped() {
        assert_eq!(
            latex_text("R1_a & 50% {x} #2 ~^\\ –"),
            "R1\\_a \\& 50\\% \\{x\\} \\#2 \\textasciitilde{}\\textasciicircum{}\\textbackslash{} --"
        );
        assert_eq!(capitalised("online"), "Online");
    }
}
