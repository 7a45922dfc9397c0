//! The recordings browser as plain data: one row per open recording with its push parameters (the
//! MIT file name's, or the native set's), its frames, split and labels, and its mean online and fixed
//! losses once it has been run; a filter over the text of every column and a sort by any column.
//!
//! The panel (`panels::browser`) draws these rows and sends [`BrowserCommand`]s; the parameters are
//! computed once per opened recording (`remember_parameters`), the losses kept as runs learn
//! (`remember_losses`), and which rows are shown in what order is kept until something it depends
//! on changes ([`ShownKey`]), so a frame builds only the rows in view: computing them reads every
//! open recording's parameters, labels file and losses, formats a name and a sort key for each and
//! sorts them — with 5,000 recordings open, 2 ms of every frame in the
//! `frame_playing_5k_recordings` benchmark and 13 ms by the app's own meter (performance.md, "Many
//! recordings open") — where the table draws only the thirty rows in view.

use std::cmp::Ordering;
use std::collections::HashMap;
use std::path::PathBuf;

use pushlab_core::experiment::split_of;
use pushlab_core::labels::LabelDocument;
use pushlab_core::labels::pipeline::key_of;
use pushlab_core::recording::{PushParameters, Recording, RecordingSet};
use serde::{Deserialize, Serialize};

use crate::app::format;
use crate::app::state::labels::labeling::{LabelTarget, Labeling};
use crate::app::state::learning::online::OnlineRun;
use crate::app::state::recordings::session::{RecordingId, Session};
use pushlab_core::learn::MeanLosses;

/// A column of the browser's table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Column {
    Set,
    Name,
    Shape,
    Surface,
    /// A native set's pushed face.
    Side,
    /// A native push's contact offset (named `Position` in files saved before the MIT columns).
    Position,
    /// The MIT file name's side index `i`.
    MitSide,
    /// The MIT file name's position along the side `s`.
    MitPosition,
    Angle,
    Speed,
    Frames,
    Split,
    Labels,
    Online,
    Fixed,
}

impl Column {
    /// Every column, in the table's order.
    pub const ALL: [Column; 15] = [
        Column::Name,
        Column::Online,
        Column::Fixed,
        Column::Shape,
        Column::Surface,
        Column::Side,
        Column::Position,
        Column::MitSide,
        Column::MitPosition,
        Column::Angle,
        Column::Speed,
        Column::Set,
        Column::Frames,
        Column::Split,
        Column::Labels,
    ];

    /// The header's text.
    pub fn title(self) -> &'static str {
        match self {
            Column::Set => "Set",
            Column::Name => "Name",
            Column::Shape => "Shape",
            Column::Surface => "Surface",
            Column::Side => "Side",
            Column::Position => "Offset",
            Column::MitSide => "MIT i",
            Column::MitPosition => "MIT s",
            Column::Angle => "Angle",
            Column::Speed => "mm/s",
            Column::Frames => "Frames",
            Column::Split => "Split",
            Column::Labels => "# labels",
            Column::Online => "Online",
            Column::Fixed => "Fixed",
        }
    }

    /// What the column holds, for the header's tooltip.
    pub fn help(self) -> &'static str {
        match self {
            Column::Set => {
                "The set: a native set's folder, or the MIT files of one surface and shape"
            }
            Column::Name => {
                "The file's short name (hover for the whole path); \"!\": loaded with warnings \
                 (frames dropped, interpolated or cut), said on hover with any notes"
            }
            Column::Shape => "The object (the MIT shape, or the box's size)",
            Column::Surface => "The surface (the setting's material)",
            Column::Side => "The pushed face of a native set's object",
            Column::Position => {
                "Where along the face the push starts: the contact offset from the face's middle, mm"
            }
            Column::MitSide => "The MIT file name's i: which side of the shape is pushed",
            Column::MitPosition => {
                "The MIT file name's s: where along that side the push starts, 0..1"
            }
            Column::Angle => "Push angle from the side's normal",
            Column::Speed => "Pusher speed, mm/s: the MIT name's v, or measured on a native push",
            Column::Frames => "Frames in the recording",
            Column::Split => "The split its labels (or setting.json) give",
            Column::Labels => "Label segments and events in its labels file",
            Column::Online => {
                "Mean online-learned loss ((ℓ_pos,x + ℓ_pos,y)/2 + ℓ_rot) over the frames learned, once run"
            }
            Column::Fixed => "Mean fixed-model loss over the same frames, once run",
        }
    }
}

/// How the table is filtered and sorted. Persisted between runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BrowserView {
    /// Rows whose text contains every word of this (case-insensitive) are shown.
    pub filter: String,
    pub sort: Column,
    pub descending: bool,
}

impl Default for BrowserView {
    fn default() -> Self {
        Self {
            filter: String::new(),
            sort: Column::Set,
            descending: false,
        }
    }
}

/// What the browser asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum BrowserCommand {
    SetFilter(String),
    /// Sort by this column; the column sorted by already flips its order.
    SortBy(Column),
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct Row<'a> {
    pub id: RecordingId,
    pub recording: &'a Recording,
    pub set: &'a str,
    /// A short name: a native file's stem, or the MIT shape and the file's number in its set.
    pub name: String,
    pub parameters: Option<&'a PushParameters>,
    pub split: Option<&'static str>,
    pub labels: usize,
    pub losses: Option<MeanLosses>,
}

impl Row<'_> {
    /// A cell as the table shows it.
    pub fn text(&self, column: Column) -> String {
        let p = self.parameters;
        let optional = |v: Option<String>| v.unwrap_or_default();
        match column {
            Column::Set => self.set.to_owned(),
            Column::Name => self.name.clone(),
            Column::Shape => optional(p.map(|p| p.shape.clone())),
            Column::Surface => optional(p.and_then(|p| p.surface.clone())),
            Column::Side => optional(p.and_then(|p| p.side.clone())),
            Column::Position => optional(
                p.and_then(|p| p.contact_offset)
                    .map(|m| format!("{:+.0} mm", m * 1e3)),
            ),
            Column::MitSide => optional(p.and_then(|p| p.mit_side).map(|i| format!("{i}"))),
            Column::MitPosition => {
                optional(p.and_then(|p| p.mit_position).map(|s| format!("{s:.2}")))
            }
            Column::Angle => optional(p.and_then(|p| p.angle_deg).map(|a| format!("{a:+.0}°"))),
            Column::Speed => optional(p.and_then(|p| p.speed_mm_s).map(|v| format!("{v:.0}"))),
            Column::Frames => self.recording.trajectory.len().to_string(),
            Column::Split => self.split.unwrap_or_default().to_owned(),
            Column::Labels => match self.labels {
                0 => String::new(),
                n => n.to_string(),
            },
            Column::Online => optional(self.losses.map(|l| format::loss(online_total(&l), 3))),
            Column::Fixed => optional(self.losses.map(|l| format::loss(fixed_total(&l), 3))),
        }
    }

    /// What the row is sorted by in `column`: a number for numeric columns, else the cell's text.
    fn sort_key(&self, column: Column) -> SortKey {
        let p = self.parameters;
        let number = match column {
            Column::Position => p.and_then(|p| p.contact_offset),
            Column::MitSide => p.and_then(|p| p.mit_side),
            Column::MitPosition => p.and_then(|p| p.mit_position),
            Column::Angle => p.and_then(|p| p.angle_deg),
            Column::Speed => p.and_then(|p| p.speed_mm_s),
            Column::Frames => Some(self.recording.trajectory.len() as f64),
            Column::Labels => Some(self.labels as f64),
            Column::Online => self.losses.map(|l| online_total(&l)),
            Column::Fixed => self.losses.map(|l| fixed_total(&l)),
            _ => return SortKey::Text(Some(self.text(column)).filter(|t| !t.is_empty())),
        };
        SortKey::Number(number)
    }

    /// Whether every word of `filter` is in one of the row's cells (or the file's name).
    fn matches(&self, filter: &str) -> bool {
        if filter.trim().is_empty() {
            return true;
        }
        let text = Column::ALL
            .iter()
            .map(|c| self.text(*c))
            .chain([self.recording.name.clone()])
            .collect::<Vec<_>>()
            .join(" ")
            .to_lowercase();
        filter
            .split_whitespace()
            .all(|word| text.contains(&word.to_lowercase()))
    }
}

/// A row's place in the sort by one column.
#[derive(Clone, Debug, PartialEq)]
enum SortKey {
    Number(Option<f64>),
    Text(Option<String>),
}

impl SortKey {
    /// Orders two keys of one column, values ascending or descending; a missing value comes after
    /// every value either way (sorting by loss shows the recordings that were run first).
    fn compare(&self, other: &Self, descending: bool) -> Ordering {
        fn missing_last<T>(
            a: &Option<T>,
            b: &Option<T>,
            cmp: impl Fn(&T, &T) -> Ordering,
        ) -> Ordering {
            match (a, b) {
                (Some(a), Some(b)) => cmp(a, b),
                (Some(_), None) => Ordering::Less,
                (None, Some(_)) => Ordering::Greater,
                (None, None) => Ordering::Equal,
            }
        }
        let direction = |order: Ordering| if descending { order.reverse() } else { order };
        match (self, other) {
            (SortKey::Number(a), SortKey::Number(b)) => {
                missing_last(a, b, |a, b| direction(a.total_cmp(b)))
            }
            (SortKey::Text(a), SortKey::Text(b)) => missing_last(a, b, |a, b| direction(a.cmp(b))),
            _ => Ordering::Equal,
        }
    }
}

fn online_total(l: &MeanLosses) -> f64 {
    l.online_pos + l.online_rot
}

fn fixed_total(l: &MeanLosses) -> f64 {
    l.fixed_pos + l.fixed_rot
}

/// Everything the browser's shown rows depend on.
#[derive(Clone, Debug, PartialEq)]
struct ShownKey {
    /// Sets are only ever added, and a set's recordings never change: the counts name the open
    /// recordings.
    sets: usize,
    recordings: usize,
    /// How many files' push parameters are read (once per new file).
    parameters: usize,
    /// The open labels files' contents (a row's labels count and split).
    labels: Vec<u64>,
    /// The losses' version, when the rows depend on them: sorted by a loss column, or filtered
    /// (the filter reads every cell). While a run learns its losses change every frame; any other
    /// view keeps its rows.
    losses: Option<u64>,
    view: BrowserView,
}

/// The rows shown, filtered and sorted, and the columns, with what they were computed from.
struct Shown {
    key: ShownKey,
    ids: Vec<RecordingId>,
    columns: Vec<Column>,
}

/// What the browser remembers about recordings, by their file, and the rows it shows.
#[derive(Default)]
pub struct BrowserMemory {
    parameters: HashMap<PathBuf, PushParameters>,
    losses: HashMap<PathBuf, MeanLosses>,
    /// Changes whenever `losses` does.
    losses_version: u64,
    /// As of the last [`BrowserMemory::refresh_shown`]; `None` before the first.
    shown: Option<Shown>,
}

impl BrowserView {
    /// Applies one browser command: the filter, or the sort (the same column again reverses it).
    pub fn apply(&mut self, command: BrowserCommand) {
        match command {
            BrowserCommand::SetFilter(filter) => self.filter = filter,
            BrowserCommand::SortBy(column) => {
                self.descending = self.sort == column && !self.descending;
                self.sort = column;
            }
        }
    }
}

impl BrowserMemory {
    /// Reads the push parameters of open recordings not seen before (once per file: a native
    /// push's speed is measured over its frames).
    pub fn remember_parameters(&mut self, session: &Session) {
        for (_, recording) in session.recordings() {
            if !self.parameters.contains_key(&recording.source) {
                (self.parameters).insert(recording.source.clone(), PushParameters::of(recording));
            }
        }
    }

    /// Forgets one recording's parameters, to be measured again (a live push, once it ended).
    pub fn forget_parameters(&mut self, source: &std::path::Path) {
        self.parameters.remove(source);
    }

    /// Forgets every recording's mean losses: they were of runs under another model.
    pub fn forget_losses(&mut self) {
        self.losses.clear();
        self.losses_version += 1;
    }

    /// Keeps the mean losses of the recording shown as its run learns.
    pub fn remember_losses(&mut self, run: Option<&OnlineRun>, recording: Option<&Recording>) {
        if let (Some(run), Some(recording)) = (run, recording)
            && let Some(losses) = run.mean_losses()
            && self.losses.get(&recording.source) != Some(&losses)
        {
            self.losses.insert(recording.source.clone(), losses);
            self.losses_version += 1;
        }
    }

    /// Computes the shown rows and columns again if anything they depend on changed since the
    /// last call (once per frame and after each command).
    pub fn refresh_shown(&mut self, session: &Session, labels: &Labeling, view: &BrowserView) {
        let by_losses = matches!(view.sort, Column::Online | Column::Fixed);
        let key = ShownKey {
            sets: session.sets.len(),
            recordings: session.recording_count(),
            parameters: self.parameters.len(),
            labels: labels.contents_key(),
            losses: (by_losses || !view.filter.trim().is_empty()).then_some(self.losses_version),
            view: view.clone(),
        };
        if self.shown.as_ref().is_some_and(|shown| shown.key == key) {
            return;
        }
        let ids = (self.rows(session, labels, view).iter())
            .map(|row| row.id)
            .collect();
        let columns = self.columns(session);
        self.shown = Some(Shown { key, ids, columns });
    }

    /// The ids of the rows shown, filtered and sorted, as of the last [`BrowserMemory::refresh_shown`].
    pub fn shown_ids(&self) -> &[RecordingId] {
        self.shown.as_ref().map_or(&[], |shown| &shown.ids)
    }

    /// The columns shown, as of the last [`BrowserMemory::refresh_shown`].
    pub fn shown_columns(&self) -> &[Column] {
        self.shown.as_ref().map_or(&[], |shown| &shown.columns)
    }

    /// One recording's row, as [`BrowserMemory::rows`] makes it.
    pub fn row_of<'a>(
        &'a self,
        id: RecordingId,
        session: &'a Session,
        labels: &Labeling,
    ) -> Option<Row<'a>> {
        let set = session.sets.get(id.set)?;
        let recording = set.recordings.get(id.recording)?;
        Some(self.row(id, recording, &set.setting.name, set_document(set, labels)))
    }

    /// The columns the table shows for the open recordings: every column, except the parameter
    /// columns no open recording has a value in (MIT's `i` and `s` with only native sets open, a
    /// native face and offset with only MIT files).
    pub fn columns(&self, session: &Session) -> Vec<Column> {
        let mut has = [false; 4];
        for (_, recording) in session.recordings() {
            if let Some(p) = self.parameters.get(&recording.source) {
                let values = [
                    p.side.is_some(),
                    p.contact_offset.is_some(),
                    p.mit_side.is_some(),
                    p.mit_position.is_some(),
                ];
                for (h, v) in has.iter_mut().zip(values) {
                    *h |= v;
                }
            }
        }
        let optional = [
            Column::Side,
            Column::Position,
            Column::MitSide,
            Column::MitPosition,
        ];
        (Column::ALL.into_iter())
            .filter(|c| optional.iter().position(|o| o == c).is_none_or(|i| has[i]))
            .collect()
    }

    /// The mean losses last seen on a recording's run.
    pub fn losses_of(&self, recording: &Recording) -> Option<MeanLosses> {
        self.losses.get(&recording.source).copied()
    }

    /// The browser's rows: every open recording that passes the view's filter, sorted by its
    /// column.
    pub fn rows<'a>(
        &'a self,
        session: &'a Session,
        labels: &Labeling,
        view: &BrowserView,
    ) -> Vec<Row<'a>> {
        let mut rows = Vec::with_capacity(session.recording_count());
        for (set_index, set) in session.sets.iter().enumerate() {
            let document = set_document(set, labels);
            for (index, recording) in set.recordings.iter().enumerate() {
                let id = RecordingId {
                    set: set_index,
                    recording: index,
                };
                let row = self.row(id, recording, &set.setting.name, document);
                if row.matches(&view.filter) {
                    rows.push(row);
                }
            }
        }
        // Each row's key once (not per comparison); stable: equal rows keep the sets' order.
        let mut keyed: Vec<(SortKey, Row<'_>)> = rows
            .drain(..)
            .map(|row| (row.sort_key(view.sort), row))
            .collect();
        keyed.sort_by(|(a, _), (b, _)| a.compare(b, view.descending));
        keyed.into_iter().map(|(_, row)| row).collect()
    }

    fn row<'a>(
        &'a self,
        id: RecordingId,
        recording: &'a Recording,
        set: &'a str,
        document: Option<&LabelDocument>,
    ) -> Row<'a> {
        let parameters = self.parameters.get(&recording.source);
        let name = match parameters {
            Some(p) if recording.name.starts_with("motion_") => {
                let rep = p
                    .repetition
                    .map(|r| format!(" rep {r}"))
                    .unwrap_or_default();
                format!("{} #{:02}{rep}", p.shape, id.recording + 1)
            }
            _ => recording.name.clone(),
        };
        let labels = document
            .zip(key_of(&recording.source))
            .and_then(|(d, key)| d.recording(&key));
        let split = split_of(recording, document.map(|d| d.set())).map(|s| s.name());
        Row {
            id,
            recording,
            set,
            name,
            parameters,
            split,
            labels: labels.map_or(0, |l| l.segments.len() + l.events.len()),
            losses: self.losses_of(recording),
        }
    }
}

/// A set's labels file, when open: its recordings share a folder and so one labels file, looked up
/// once per set.
fn set_document<'a>(set: &RecordingSet, labels: &'a Labeling) -> Option<&'a LabelDocument> {
    (set.recordings.first())
        .and_then(LabelTarget::of)
        .and_then(|t| labels.document(&t.document))
}

#[cfg(test)]
mod tests;
