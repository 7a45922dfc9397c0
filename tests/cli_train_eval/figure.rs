//! eval's figure as a vector file: `--plot OUT.svg` draws what the PNG shows, with each smoothed
//! mean as one polyline, the axis labels, captions and legend as text, and the bundled font
//! carried in the file; `--plot OUT.pdf` renders (poppler's `pdftoppm`) like the PNG and its words
//! are text (`pdftotext`); a name of another kind is refused before anything runs.

use super::*;
use crate::skip;

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
    let pdf = dir.join("fig.eps");
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
            .contains("fig.eps: expected a .png, .svg or .pdf file name, got .eps"),
        "{}",
        run.stderr
    );
    assert!(!pdf.exists());
}

/// The mean of each `block` × `block` square of an RGB image `width` wide, grey levels.
fn blocks(rgb: &[u8], width: usize, block: usize) -> Vec<f64> {
    let height = rgb.len() / 3 / width;
    let mut means = Vec::new();
    for by in 0..height / block {
        for bx in 0..width / block {
            let mut sum = 0.0;
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let at = (y * width + x) * 3;
                    sum += rgb[at..at + 3].iter().map(|&v| f64::from(v)).sum::<f64>() / 3.0;
                }
            }
            means.push(sum / (block * block) as f64);
        }
    }
    means
}

#[test]
fn eval_plots_a_pdf_that_renders_like_the_png_with_its_words_as_text() {
    let have = |program: &str| {
        std::process::Command::new(program)
            .arg("-v")
            .output()
            .is_ok()
    };
    if !have("pdftoppm") || !have("pdftotext") {
        skip::skip("poppler's pdftoppm and pdftotext on the PATH (apt install poppler-utils)");
        return;
    }
    let dir = temp_dir("figure-pdf");
    let online = sample("box1-paper-ur-front", "online_000.csv");
    for name in ["fig.pdf", "fig.png"] {
        let run = pushlab(&[
            "eval",
            "--model",
            &default_model(),
            "--online",
            &online,
            "--plot",
            &dir.join(name).display().to_string(),
        ]);
        assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    }
    let pdf = dir.join("fig.pdf");
    let bytes = std::fs::read(&pdf).unwrap();
    assert!(bytes.starts_with(b"%PDF-1.7"));
    // Tens of kB: the font is embedded as the subset of the glyphs the figure uses (the whole
    // font file is 410 kB).
    assert!(bytes.len() < 60_000, "{} bytes", bytes.len());
    // Rendered at 72 dpi a point is a pixel: the PNG's size.
    let rendered = std::process::Command::new("pdftoppm")
        .args(["-r", "72", "-png", "-singlefile"])
        .arg(&pdf)
        .arg(dir.join("page"))
        .output()
        .unwrap();
    assert!(
        rendered.status.success(),
        "{}",
        String::from_utf8_lossy(&rendered.stderr)
    );
    let read = |name: &str| image::open(dir.join(name)).unwrap().to_rgb8();
    let (page, png) = (read("page.png"), read("fig.png"));
    assert_eq!(page.dimensions(), png.dimensions());
    assert_eq!(png.dimensions(), (1000, 400));
    // Like the PNG: 8 × 8 squares compared, as an eye at a distance would. Anti-aliasing and
    // kerning differ by a grey level or two on average; a line or a word missing or moved by a few
    // pixels changes a square by tens of levels.
    let (a, b) = (
        blocks(page.as_raw(), 1000, 8),
        blocks(png.as_raw(), 1000, 8),
    );
    let differences: Vec<f64> = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).collect();
    let mean = differences.iter().sum::<f64>() / differences.len() as f64;
    let far = differences.iter().filter(|d| **d > 40.0).count();
    assert!(
        mean < 3.0 && far < differences.len() / 100,
        "mean difference {mean:.2} levels, {far} of {} squares over 40",
        differences.len()
    );
    // Text as text, in the embedded font.
    let words = std::process::Command::new("pdftotext")
        .arg(&pdf)
        .arg("-")
        .output()
        .unwrap();
    let words = String::from_utf8_lossy(&words.stdout);
    for word in [
        "time step",
        "online loss",
        "Fixed",
        "Online",
        "mean loss: pos (solid), rot (dashed)",
    ] {
        assert!(words.contains(word), "{word:?} in {words}");
    }
    let fonts = std::process::Command::new("pdffonts")
        .arg(&pdf)
        .output()
        .unwrap();
    let fonts = String::from_utf8_lossy(&fonts.stdout);
    assert!(
        fonts.contains("LiberationSans") && fonts.contains("yes"),
        "embedded: {fonts}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
