//! eval's figure as a vector file: `--plot OUT.svg` draws what the PNG shows, with each smoothed
//! mean as one polyline, the axis labels, captions and legend as text, and the bundled font
//! carried in the file; a name of another kind is refused before anything runs.

use super::*;

fn default_model() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/default-model.json")
        .display()
        .to_string()
}

#[test]
fn eval_plots_an_svg_whose_series_are_lines_and_whose_words_are_text() {
    let dir = temp_dir("figure-svg");
    let svg = dir.join("fig.svg");
    let online = sample("box1-paper-ur-front", "online_000.csv");
    let run = pushlab(&[
        "eval",
        "--model",
        &default_model(),
        "--online",
        &online,
        "--plot",
        &svg.display().to_string(),
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let text = std::fs::read_to_string(&svg).unwrap();
    let document = roxmltree::Document::parse(&text).expect("the SVG is XML");
    let root = document.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(
        (root.attribute("width"), root.attribute("height")),
        (Some("1000"), Some("400"))
    );
    let words: Vec<&str> = (root.descendants())
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(str::trim)
        .collect();
    for (word, times) in [
        ("time step", 2),
        ("online loss", 2),
        ("Fixed", 2),
        ("Online", 2),
        ("total loss (mean ± 1 std)", 1),
        ("mean loss: pos (solid), rot (dashed)", 1),
    ] {
        let found = words.iter().filter(|w| **w == word).count();
        assert_eq!(found, times, "{word:?} in {words:?}");
    }
    // The solid means: fixed and online on each panel, one polyline each, over every step (a
    // 101-frame push at horizon 10: 91 samples). Dashes and the legend's marks are short.
    let long: Vec<(&str, usize)> = (root.descendants())
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            let points = n
                .attribute("points")
                .unwrap_or("")
                .split_whitespace()
                .count();
            (n.attribute("stroke").unwrap_or(""), points)
        })
        .filter(|(_, points)| *points > 50)
        .collect();
    assert_eq!(
        long,
        [
            ("#1F77B4", 91),
            ("#FF7F0E", 91),
            ("#1F77B4", 91),
            ("#FF7F0E", 91)
        ],
        "fixed blue, online orange"
    );
    // The font travels with the file: a TrueType file (its first bytes 00 01 00 00) as a data URL.
    let style = (root.descendants())
        .find(|n| n.has_tag_name("style"))
        .and_then(|n| n.text())
        .expect("a style");
    assert!(
        style.contains("font-family:pushlab-figure;src:url(data:font/ttf;base64,AAEAAA"),
        "{style:.120}"
    );
    assert!(text.contains(
        "font-family=\"pushlab-figure, 'Liberation Sans', Arial, Helvetica, sans-serif\""
    ));

    // Another kind of file is refused before the model is even loaded.
    let pdf = dir.join("fig.pdf");
    let run = pushlab(&[
        "eval",
        "--model",
        &default_model(),
        "--online",
        &online,
        "--plot",
        &pdf.display().to_string(),
    ]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("fig.pdf: expected a .png or .svg file name, got .pdf"),
        "{}",
        run.stderr
    );
    assert!(!pdf.exists());
}
