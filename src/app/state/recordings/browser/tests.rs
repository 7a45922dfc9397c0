//! The browser's rows: filter, sort, losses and the MIT and native columns.

use super::*;
use std::path::Path;

use crate::app::state::SessionCommand;
use crate::app::state::models::Models;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command, Persisted};

fn state_on(dir: &Path) -> AppState {
    let mut state = AppState::new(Persisted::default(), Models::default());
    state.open_blocking(&[dir.to_path_buf()]);
    assert!(
        state.session.problems.is_empty(),
        "{:?}",
        state.session.problems
    );
    state
}

fn sample_data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("sample-data")
}

fn column(state: &AppState, c: Column) -> Vec<String> {
    state.browser_rows().iter().map(|r| r.text(c)).collect()
}

#[test]
fn the_filter_keeps_rows_with_every_word_and_sorting_twice_reverses() {
    let mut state = state_on(&sample_data());
    assert_eq!(state.browser_rows().len(), 324);
    state.apply(Command::Browser(BrowserCommand::SetFilter(
        "ONLINE box2".into(),
    )));
    let rows = state.browser_rows();
    // Three box2 sets with nine online pushes each.
    assert_eq!(rows.len(), 27);
    assert!(
        rows.iter()
            .all(|r| r.set.starts_with("box2") && r.name.starts_with("online_"))
    );

    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Angle)));
    let angle = |r: &Row<'_>| r.parameters.and_then(|p| p.angle_deg).expect("an angle");
    let rows = state.browser_rows();
    assert!(rows.windows(2).all(|w| angle(&w[0]) <= angle(&w[1])));
    assert_eq!(angle(&rows[0]), -15.0);
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Angle)));
    let rows = state.browser_rows();
    assert!(rows.windows(2).all(|w| angle(&w[0]) >= angle(&w[1])));
    assert_eq!(column(&state, Column::Angle)[0], "+25°");
    assert_eq!(
        state.persisted().browser.sort,
        Column::Angle,
        "kept across restarts"
    );
}

#[test]
fn a_run_puts_its_mean_losses_in_its_row_and_rows_with_losses_sort_first() {
    let mut state = state_on(&sample_data().join("box1-paper-center-front"));
    let shown = state.session.selected.expect("a selection");
    assert!(state.browser_rows().iter().all(|r| r.losses.is_none()));
    state.settings.learn_while_playing = true;
    for _ in 0..30 {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    let expected = state
        .run
        .as_ref()
        .and_then(|r| r.mean_losses())
        .expect("learned");
    assert_eq!(expected.frames, 30);
    // Another recording: the first one's losses stay in its row.
    let other = crate::app::state::recordings::session::RecordingId {
        set: shown.set,
        recording: 5,
    };
    state.apply(Command::Session(SessionCommand::Select(other)));
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Online)));
    let rows = state.browser_rows();
    assert_eq!(rows[0].id, shown);
    assert_eq!(rows[0].losses, Some(expected));
    assert_eq!(
        rows[0].text(Column::Online),
        crate::app::format::loss(expected.online_pos + expected.online_rot, 3)
    );
    assert!(rows[1..].iter().all(|r| r.losses.is_none()));
    // Descending too: the recording that was run comes first, the others after it.
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Online)));
    assert!(state.settings.browser.descending);
    assert_eq!(state.browser_rows()[0].id, shown);
}

#[test]
fn mit_files_get_short_names_and_their_parameters_as_columns() {
    let Some(dir) =
        crate::skip::shared(Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push-abs-train")
    else {
        return;
    };
    let mut state = state_on(&dir);
    state.apply(Command::Browser(BrowserCommand::SetFilter("hex".into())));
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Speed)));
    let rows = state.browser_rows();
    assert_eq!(rows.len(), 14, "the hex files");
    let names = column(&state, Column::Name);
    assert!(names.iter().all(|n| n.starts_with("hex #")), "{names:?}");
    assert!(names.iter().all(|n| n.len() <= 12), "short: {names:?}");
    let speeds = column(&state, Column::Speed);
    assert_eq!(speeds.first().map(String::as_str), Some("50"));
    assert_eq!(speeds.last().map(String::as_str), Some("100"));
    assert!(column(&state, Column::Surface).iter().all(|s| s == "abs"));
    // MIT's i and s in their own columns, not in the native face and offset ones (issue 26.4).
    let positions = column(&state, Column::MitPosition);
    assert!(
        positions
            .iter()
            .all(|s| s.parse::<f64>().is_ok_and(|s| (0.0..=1.0).contains(&s))),
        "{positions:?}"
    );
    let sides = column(&state, Column::MitSide);
    assert!(sides.iter().all(|i| i.parse::<f64>().is_ok()), "{sides:?}");
    assert!(column(&state, Column::Side).iter().all(String::is_empty));
    assert!(
        column(&state, Column::Position)
            .iter()
            .all(String::is_empty)
    );
    // Only MIT files open: the native columns are not shown at all.
    let shown = state.browser_columns();
    assert!(shown.contains(&Column::MitSide) && shown.contains(&Column::MitPosition));
    assert!(!shown.contains(&Column::Side) && !shown.contains(&Column::Position));
}

#[test]
fn native_sets_show_their_face_and_offset_and_no_mit_columns() {
    let state = state_on(&sample_data().join("box1-paper-center-left"));
    let shown = state.browser_columns();
    assert!(shown.contains(&Column::Side) && shown.contains(&Column::Position));
    assert!(!shown.contains(&Column::MitSide) && !shown.contains(&Column::MitPosition));
    assert!(column(&state, Column::Side).iter().all(|s| s == "left"));
    let offsets = column(&state, Column::Position);
    assert!(
        offsets
            .iter()
            .all(|o| o.ends_with(" mm") && o.starts_with(['+', '-'])),
        "{offsets:?}"
    );
}

/// What the panel draws, kept between frames, is what the rows are now.
fn assert_drawn_rows_are_current(state: &AppState, when: &str) {
    let now: Vec<RecordingId> = state.browser_rows().iter().map(|r| r.id).collect();
    assert_eq!(state.browser_shown(), now.as_slice(), "{when}");
}

#[test]
fn the_rows_drawn_follow_the_filter_the_sort_a_new_set_labels_and_losses() {
    use crate::app::state::labels::labeling::LabelAction;
    use crate::app::state::labels::labeling::tests::copy_of_sample_set;
    let dir = copy_of_sample_set("browser-drawn");
    let mut state = state_on(&dir);
    state.apply(Command::Browser(BrowserCommand::SetFilter("online".into())));
    assert_drawn_rows_are_current(&state, "filtered");
    assert_eq!(state.browser_shown().len(), 9);
    // A set opened: its rows are drawn.
    state.open_blocking(&[sample_data().join("box1-paper-lr-front")]);
    assert_drawn_rows_are_current(&state, "a set opened");
    assert_eq!(state.browser_shown().len(), 18);
    // Sorted by labels, a recording labelled comes first once labelled.
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Labels)));
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Labels)));
    let last = *state.browser_shown().last().expect("rows");
    state.apply(Command::Session(SessionCommand::Select(last)));
    state.apply(Command::Label(LabelAction::SetInPoint));
    state.apply(Command::Timeline(TimelineCommand::SeekTo(5)));
    state.apply(Command::Label(LabelAction::SetActive("contact".into())));
    state.apply(Command::Label(LabelAction::PaintFromInPoint));
    assert_drawn_rows_are_current(&state, "labelled");
    assert_eq!(state.browser_shown()[0], last, "the labelled row first");
    // Sorted by the online loss, the recording learning comes first as its losses appear.
    state.apply(Command::Browser(BrowserCommand::SortBy(Column::Online)));
    state.settings.learn_while_playing = true;
    state.apply(Command::Timeline(TimelineCommand::SeekTo(0)));
    let first = state.browser_shown()[0];
    state.apply(Command::Session(SessionCommand::Select(
        *state.browser_shown().last().expect("rows"),
    )));
    let learning = state.session.selected.expect("selected");
    assert_ne!(first, learning);
    for _ in 0..20 {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    assert_drawn_rows_are_current(&state, "losses learned");
    assert_eq!(state.browser_shown()[0], learning);
    let _ = std::fs::remove_dir_all(&dir);
}
