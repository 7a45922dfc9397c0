//! File → Export plots as SVG or PDF…: the run shown as a vector figure — the losses and θ as the plots
//! panel draws them, each series a polyline over the frames learned, the panels' titles and legends
//! as text — written atomically; a name of another kind is refused, naming it.

use crate::common;

use pushlab::app::initial_state;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, FileCommand, Persisted};

#[test]
fn the_plots_export_as_an_svg_whose_series_are_lines_and_whose_words_are_text() {
    let dir = common::scratch_dir("export-plots");
    let set = common::sample_dir("box1-paper-ur-front");
    let mut state = initial_state(&[set.join("online_000.csv")], Persisted::default());
    for _ in 0..40 {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    let learned = state.run().expect("a run").frontier();
    assert_eq!(learned, 40);

    let svg = dir.join("plots.svg");
    state.apply(Command::File(FileCommand::ExportPlots(svg.clone())));
    assert_eq!(
        state.status(),
        Some(format!("exported the plots of 40 frames to {}", svg.display()).as_str())
    );
    let text = std::fs::read_to_string(&svg).expect("the figure is written");
    let document = roxmltree::Document::parse(&text).expect("the SVG is XML");
    let root = document.root_element();
    let words: Vec<&str> = (root.descendants())
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(str::trim)
        .collect();
    for (word, times) in [
        ("Position loss", 1),
        ("Rotation loss", 1),
        ("COM offset x [mm]", 1),
        ("COM offset y [mm]", 1),
        ("h [mm]", 1),
        ("Fixed (moving avg 25)", 2),
        ("Online (moving avg 25)", 2),
        ("θ_online", 3),
        // The simulated set knows its COM and h.
        ("true", 3),
    ] {
        let found = words.iter().filter(|w| **w == word).count();
        assert_eq!(found, times, "{word:?} in {words:?}");
    }
    // θ over the frames learned (41 checkpoints: frame 0 to 40), orange, one polyline per component;
    // the fixed loss over every sample of the 101-frame push at horizon 10 (91), blue.
    let lines: Vec<(String, usize)> = (root.descendants())
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| {
            let points = (n.attribute("points").unwrap_or(""))
                .split_whitespace()
                .count();
            (n.attribute("stroke").unwrap_or("").to_owned(), points)
        })
        .collect();
    let count = |stroke: &str, points: usize| {
        (lines.iter())
            .filter(|(s, p)| s == stroke && *p == points)
            .count()
    };
    assert_eq!(count("#FF7F0E", 41), 3, "{lines:?}");
    assert!(count("#1F77B4", 91) >= 2, "{lines:?}");

    // A PDF by its name: the same figure, its words as text in the embedded font.
    let pdf = dir.join("plots.pdf");
    state.apply(Command::File(FileCommand::ExportPlots(pdf.clone())));
    let bytes = std::fs::read(&pdf).expect("the PDF is written");
    assert!(bytes.starts_with(b"%PDF-1.7") && bytes.trim_ascii_end().ends_with(b"%%EOF"));
    // The font embedded is the subset of the glyphs used, not the whole 410 kB file.
    assert!(bytes.len() < 60_000, "{} bytes", bytes.len());
    // Another kind of file is refused by name, and nothing is written.
    let eps = dir.join("plots.eps");
    state.apply(Command::File(FileCommand::ExportPlots(eps.clone())));
    let said = state.status().unwrap_or_default().to_owned();
    assert!(
        said.contains("plots.eps: expected a .png, .svg or .pdf file name, got .eps"),
        "{said}"
    );
    assert!(!eps.exists());
    std::fs::remove_dir_all(&dir).ok();
}
