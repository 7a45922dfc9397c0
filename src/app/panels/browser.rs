//! The recordings browser: a table of every open recording — short name, the push's parameters (the
//! MIT file name's, or the native set's), frames, split, and the mean online and fixed loss once it
//! has been run — with a filter box and a sort by any column (click a header; again to reverse). The
//! rows, the filter and the sort are the state's (`state::recordings::browser`); this panel draws them and sends
//! commands. Load problems are listed below the table.

use eframe::egui::{self, Color32, RichText};
use egui_extras::{Column as TableColumn, TableBuilder};

use crate::app::state::SessionCommand;
use crate::app::state::recordings::browser::{BrowserCommand, Column, Row};
use crate::app::state::recordings::session::RecordingId;
use crate::app::state::sources::bag_import::BagCommand;
use crate::app::state::sources::dataset_import::DatasetCommand;
use crate::app::state::{AppState, Command};

/// Height of a table row, points.
const ROW_HEIGHT: f32 = 18.0;

/// Draws the browser.
pub fn ui(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    ui.heading("Recordings");
    if state.session().sets.is_empty() {
        ui.label("Nothing open. Use File > Open, or drop files or folders here.");
    }
    ui.horizontal(|ui| {
        let label = ui.label("Filter");
        let mut filter = state.settings().browser.filter.clone();
        let edit = ui
            .add(
                egui::TextEdit::singleline(&mut filter)
                    .hint_text("words in any column, e.g. hex online")
                    .desired_width(ui.available_width() - 8.0),
            )
            .labelled_by(label.id);
        if edit.changed() {
            commands.push(Command::Browser(BrowserCommand::SetFilter(filter)));
        }
    });
    let rows = state.browser_shown();
    ui.weak(format!(
        "{} of {} recordings",
        rows.len(),
        state.session().recording_count()
    ));
    let table_height = ui.available_height() - problems_height(state);
    egui::ScrollArea::horizontal()
        .id_salt("browser-columns")
        .show(ui, |ui| {
            ui.set_height(table_height.max(ROW_HEIGHT * 3.0));
            table(ui, state, rows, commands);
        });
    problems(ui, state, commands);
}

/// The table; only the rows in view are built (`body.rows` asks for those alone).
/// A recording selected from elsewhere (a link, a drop, a demo, a sandbox push) is scrolled into
/// sight once, when the selection changes; a row clicked is in sight already.
fn table(ui: &mut egui::Ui, state: &AppState, rows: &[RecordingId], commands: &mut Vec<Command>) {
    ui.spacing_mut().item_spacing.x = 4.0;
    let selected = state.session().selected;
    let scrolled_id = egui::Id::unique("pushlab-browser-scrolled-to");
    let scrolled_to: Option<RecordingId> = ui.data(|d| d.get_temp(scrolled_id)).flatten();
    let scroll_to = (scrolled_to != selected)
        .then(|| selected.and_then(|id| rows.iter().position(|r| *r == id)))
        .flatten();
    if scroll_to.is_some() {
        ui.data_mut(|d| d.insert_temp(scrolled_id, selected));
    }
    let mut builder = TableBuilder::new(ui)
        .id_salt("browser-table")
        .striped(true)
        .resizable(true)
        .auto_shrink([false, false])
        .max_scroll_height(f32::INFINITY)
        .cell_layout(egui::Layout::left_to_right(egui::Align::Center));
    if let Some(index) = scroll_to {
        builder = builder.scroll_to_row(index, None);
    }
    let columns = state.browser_columns();
    for &column in columns {
        builder = builder.column(width(column));
    }
    let sorted = (
        state.settings().browser.sort,
        state.settings().browser.descending,
    );
    builder
        .header(ROW_HEIGHT + 2.0, |mut header| {
            for &column in columns {
                header.col(|ui| {
                    if ui
                        .add(egui::Button::new(header_text(ui, column, sorted)).frame(false))
                        .on_hover_text(column.help())
                        .clicked()
                    {
                        commands.push(Command::Browser(BrowserCommand::SortBy(column)));
                    }
                });
            }
        })
        .body(|body| {
            body.rows(ROW_HEIGHT, rows.len(), |mut table_row| {
                let Some(row) = state.browser_row(rows[table_row.index()]) else {
                    return;
                };
                let selected = state.session().selected == Some(row.id);
                table_row.set_selected(selected);
                for &column in columns {
                    table_row.col(|ui| cell(ui, state, &row, column, selected, commands));
                }
            });
        });
}

/// A header: the column's title, and ▲ or ▼ when the table is sorted by it (in the monospace font,
/// which has the triangles).
fn header_text(
    ui: &egui::Ui,
    column: Column,
    (sort, descending): (Column, bool),
) -> egui::text::LayoutJob {
    let mut job = egui::text::LayoutJob::default();
    let color = ui.visuals().strong_text_color();
    let font = egui::TextStyle::Body.resolve(ui.style());
    job.append(column.title(), 0.0, egui::TextFormat::simple(font, color));
    if sort == column {
        let arrow = if descending { " ▼" } else { " ▲" };
        let mono = egui::TextStyle::Monospace.resolve(ui.style());
        job.append(arrow, 0.0, egui::TextFormat::simple(mono, color));
    }
    job
}

/// One cell; the name is the button that selects the recording, with the details on hover.
fn cell(
    ui: &mut egui::Ui,
    state: &AppState,
    row: &Row<'_>,
    column: Column,
    selected: bool,
    commands: &mut Vec<Command>,
) {
    let text = row.text(column);
    if column != Column::Name {
        ui.add(egui::Label::new(text).selectable(false).truncate());
        return;
    }
    let response = ui
        .add(egui::Button::selectable(selected, name_text(ui, &text, row)).truncate())
        .on_hover_ui(|ui| details(ui, state, row));
    if response.clicked() && !selected {
        commands.push(Command::Session(SessionCommand::Select(row.id)));
    }
}

/// A recording's name, after a "!" in the warning colour when it loaded with warnings (rows dropped,
/// a bag cut short): marked where it is listed, said on hover. Notes (an angle unwrapped, streams
/// resampled) are said on hover only. (The default fonts have no warning sign.)
fn name_text(ui: &egui::Ui, name: &str, row: &Row<'_>) -> egui::text::LayoutJob {
    let font = egui::TextStyle::Button.resolve(ui.style());
    let mut job = egui::text::LayoutJob::default();
    if !row.recording.warnings.is_empty() {
        let warn = egui::TextFormat::simple(font.clone(), ui.visuals().warn_fg_color);
        job.append("! ", 0.0, warn);
    }
    // Color32::PLACEHOLDER: egui draws the name in the button's own colour, selected or not.
    job.append(
        name,
        0.0,
        egui::TextFormat::simple(font, Color32::PLACEHOLDER),
    );
    job
}

/// What the name's tooltip says: the file, its rate, labels, load warnings and notes, its losses.
fn details(ui: &mut egui::Ui, state: &AppState, row: &Row<'_>) {
    let recording = row.recording;
    ui.label(recording.source.display().to_string());
    ui.label(format!(
        "{} frames, {:.1} s at {:.0} Hz",
        recording.trajectory.len(),
        recording.trajectory.duration(),
        recording.trajectory.mean_rate_hz()
    ));
    match row.labels {
        0 => {}
        1 => {
            ui.label("1 label");
        }
        n => {
            ui.label(format!("{n} labels"));
        }
    }
    if let Some(l) = state.remembered_losses(recording) {
        ui.label(format!(
            "mean over {} learned frames: online pos {:.4} rot {:.4}, fixed pos {:.4} rot {:.4}",
            l.frames, l.online_pos, l.online_rot, l.fixed_pos, l.fixed_rot
        ));
    }
    for warning in &recording.warnings {
        ui.colored_label(ui.visuals().warn_fg_color, warning);
    }
    for note in &recording.notes {
        ui.weak(format!("note: {note}"));
    }
}

/// Initial widths: the name, the losses and the push's parameters fit the browser's default width;
/// the set, frames, split and labels are a horizontal scroll away.
fn width(column: Column) -> TableColumn {
    let points = match column {
        Column::Name => 88.0,
        Column::Online | Column::Fixed => 44.0,
        Column::Shape => 56.0,
        Column::Surface => 46.0,
        Column::Position => 58.0,
        Column::Side | Column::Angle | Column::Speed | Column::MitPosition => 38.0,
        Column::MitSide => 30.0,
        Column::Set => 120.0,
        Column::Frames | Column::Split | Column::Labels => 48.0,
    };
    TableColumn::initial(points).at_least(24.0).clip(true)
}

fn problems_height(state: &AppState) -> f32 {
    if state.session().problems.is_empty() {
        0.0
    } else {
        160.0
    }
}

/// Load problems, each naming the file and the reason; they stay until dismissed.
fn problems(ui: &mut egui::Ui, state: &AppState, commands: &mut Vec<Command>) {
    if state.session().problems.is_empty() {
        return;
    }
    ui.separator();
    ui.horizontal(|ui| {
        ui.colored_label(
            ui.visuals().error_fg_color,
            format!(
                "{} file(s) could not be loaded",
                state.session().problems.len()
            ),
        );
        if ui.small_button("Dismiss").clicked() {
            commands.push(Command::Session(SessionCommand::DismissProblems));
        }
    });
    egui::ScrollArea::vertical()
        .id_salt("problems")
        .max_height(130.0)
        .show(ui, |ui| {
            for problem in &state.session().problems {
                ui.label(RichText::new(&problem.message).small())
                    .on_hover_text(problem.path.display().to_string());
                if problem.bag_to_choose
                    && ui
                        .small_button("Choose topics…")
                        .on_hover_text("choose this bag's pusher and object topics and its object")
                        .clicked()
                {
                    commands.push(Command::Bag(BagCommand::ChooseAgain(problem.path.clone())));
                }
                if problem.dataset_to_choose
                    && ui
                        .small_button("Choose features…")
                        .on_hover_text(
                            "choose which features are the pusher and the T, and the scale",
                        )
                        .clicked()
                {
                    let path = problem.path.clone();
                    commands.push(Command::Dataset(DatasetCommand::Choose(path)));
                }
            }
        });
}
