//! The recordings browser driven as a user would: type a filter, sort by clicking a column's header,
//! pick a recording by its name, and see a recording's mean losses once it has been run.

use crate::common;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use pushlab::app::state::Persisted;
use pushlab::app::state::recordings::browser::Column;
use pushlab::app::{PushlabApp, initial_state};

fn app() -> Harness<'static, PushlabApp> {
    let app = PushlabApp::new(initial_state(&[], Persisted::default()));
    assert_eq!(
        app.state.session().recording_count(),
        324,
        "the sample data opens"
    );
    common::harness(app, 0.05)
}

fn shows(harness: &Harness<'_, PushlabApp>, text: &str) -> bool {
    harness.query_all_by_label_contains(text).next().is_some()
}

fn names(harness: &Harness<'_, PushlabApp>) -> Vec<String> {
    harness
        .state()
        .state
        .browser_rows()
        .iter()
        .map(|r| r.name.clone())
        .collect()
}

#[test]
fn filtering_sorting_and_picking_a_recording_from_the_table() {
    let mut harness = app();
    harness.run_steps(2);
    assert!(shows(&harness, "324 of 324 recordings"));

    harness
        .get_by_role_and_label(egui::accesskit::Role::TextInput, "Filter")
        .click();
    harness.run_steps(1);
    harness.event(egui::Event::Text("online box2-plastic-lr".to_owned()));
    harness.run_steps(2);
    assert!(
        shows(&harness, "9 of 324 recordings"),
        "the filter narrowed the table"
    );
    assert!(names(&harness).iter().all(|n| n.starts_with("online_")));

    // Sort by the push angle, then reverse it.
    harness.get_by_label("Angle").click();
    harness.run_steps(2);
    assert!(shows(&harness, "Angle ▲"), "the header shows the sort");
    let angles = |h: &Harness<'_, PushlabApp>| -> Vec<String> {
        h.state()
            .state
            .browser_rows()
            .iter()
            .map(|r| r.text(Column::Angle))
            .collect()
    };
    assert_eq!(angles(&harness)[..3], ["-15°", "-15°", "-15°"]);
    harness.get_by_label("Angle ▲").click();
    harness.run_steps(2);
    assert_eq!(angles(&harness)[..3], ["+25°", "+25°", "+25°"]);

    // Pick the first row by its name: it is shown and starts its own run.
    let (id, name) = {
        let rows = harness.state().state.browser_rows();
        (rows[0].id, rows[0].name.clone())
    };
    assert_ne!(harness.state().state.session().selected, Some(id));
    harness.get_by_label(&name).click();
    harness.run_steps(2);
    let state = &harness.state().state;
    assert_eq!(state.session().selected, Some(id));
    assert_eq!(
        state.recording().map(|r| r.name.as_str()),
        Some(name.as_str())
    );
}

#[test]
fn a_recording_run_shows_its_mean_losses_in_the_table() {
    let mut harness = app();
    harness.run_steps(2);
    let shown = harness
        .state()
        .state
        .session()
        .selected
        .expect("a recording");
    let row_of = |h: &Harness<'_, PushlabApp>| {
        let state = &h.state().state;
        let rows = state.browser_rows();
        let row = rows.iter().find(|r| r.id == shown).expect("its row");
        (row.text(Column::Online), row.text(Column::Fixed))
    };
    assert_eq!(
        row_of(&harness),
        (String::new(), String::new()),
        "not run yet"
    );
    for _ in 0..25 {
        harness.key_press(egui::Key::ArrowRight);
        harness.run_steps(1);
    }
    let (online, fixed) = row_of(&harness);
    let mean = harness
        .state()
        .state
        .run()
        .as_ref()
        .and_then(|r| r.mean_losses())
        .expect("25 frames learned");
    assert_eq!(online, format!("{:.3}", mean.online_pos + mean.online_rot));
    assert_eq!(fixed, format!("{:.3}", mean.fixed_pos + mean.fixed_rot));
    assert!(shows(&harness, &online), "the table shows {online}");
}
