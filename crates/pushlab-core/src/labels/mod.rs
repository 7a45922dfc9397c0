//! Labels: what each recording is (metadata, split) and what happens in it (contact, sticking,
//! slipping, bad tracking), stored in a sidecar file beside the recordings.
//!
//! The parts, each in its own module:
//! - [`schema`]: label names, colours, hotkeys, exclusive groups, ranges vs. point events;
//! - [`segments`]: per-frame segments (half-open frame ranges) and the painting rules;
//! - [`metadata`]: per-recording fields (object, material, COM, pushing side, split, notes);
//! - [`document`]: every edit as a [`Command`] applied to a [`LabelDocument`], with undo/redo and
//!   revert — what the app's labels panel drives;
//! - [`file`]: the versioned `pushlab-labels.json` format, its errors and atomic saves;
//! - [`export`]: JSON and CSV exports with frame times;
//! - [`pipeline`]: what training and evaluation ask of labels (splits, frames to skip, per-label
//!   means), independent of the model code;
//! - [`propose`]: label proposals from physics (contact, sticking / slipping, bad tracking), with a
//!   confidence and a reason per frame, for a person to accept;
//! - [`compare`]: frame precision, recall and F1 of one labels file against a reference.
//!
//! Recordings are keyed by their file name (`push_003.csv`), relative to the folder holding the
//! labels file; the recordings themselves are never written.

pub mod compare;
pub mod document;
pub mod export;
pub mod file;
pub mod metadata;
pub mod pipeline;
pub mod propose;
pub mod schema;
pub mod segments;

use std::collections::BTreeMap;
use std::ops::Range;

use serde::{Deserialize, Serialize};

pub use document::{Autosave, Command, EditError, LabelDocument, SaveState};
pub use file::{LABELS_FILE_NAME, LabelFileError};
pub use metadata::{MetaField, RecordingMeta, Split};
pub use schema::{LabelDef, LabelKind, LabelSchema, Rgb};
pub use segments::{Event, Segment};

/// Everything known about one recording: its metadata, range segments and point events.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordingLabels {
    /// Object, material, COM, side, split, notes.
    #[serde(default, skip_serializing_if = "RecordingMeta::is_empty")]
    pub meta: RecordingMeta,
    /// Range labels, sorted by start; see [`segments`] for the invariants.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segments: Vec<Segment>,
    /// Point events, sorted by frame.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<Event>,
}

impl RecordingLabels {
    /// Whether nothing at all is labelled (such recordings are left out of the file).
    pub fn is_empty(&self) -> bool {
        self.meta.is_empty() && self.segments.is_empty() && self.events.is_empty()
    }

    /// The range segments covering `frame`, for the app's "labels here" readout.
    pub fn segments_at(&self, frame: usize) -> impl Iterator<Item = &Segment> {
        self.segments.iter().filter(move |s| s.contains(frame))
    }

    /// Whether `label` covers `frame`.
    pub fn has_label_at(&self, label: &str, frame: usize) -> bool {
        self.segments_at(frame).any(|s| s.label == label)
    }

    /// One flag per frame of a recording `frame_count` frames long: `true` where the range label
    /// `label` covers the frame (segments past the end are cut). What scripts take as a label's
    /// per-frame mask.
    pub fn mask(&self, label: &str, frame_count: usize) -> Vec<bool> {
        let mut mask = vec![false; frame_count];
        for s in self.segments.iter().filter(|s| s.label == label) {
            let end = s.end.min(frame_count);
            mask[s.start.min(end)..end].fill(true);
        }
        mask
    }

    /// The range labels used, each once, in the order their first segment starts.
    pub fn range_labels(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for s in &self.segments {
            if !names.contains(&s.label.as_str()) {
                names.push(&s.label);
            }
        }
        names
    }

    /// The segments and events touching `frames`, for drawing the visible part of a timeline.
    pub fn segments_in(&self, frames: Range<usize>) -> impl Iterator<Item = &Segment> {
        self.segments
            .iter()
            .filter(move |s| s.start < frames.end && frames.start < s.end)
    }

    /// The nearest frame after `frame` where a segment starts or ends or an event sits: where the
    /// "next label" key jumps. A segment's end is reported as its last frame.
    pub fn next_boundary(&self, frame: usize) -> Option<usize> {
        self.boundaries().filter(|&f| f > frame).min()
    }

    /// The nearest such frame before `frame`: where the "previous label" key jumps.
    pub fn previous_boundary(&self, frame: usize) -> Option<usize> {
        self.boundaries().filter(|&f| f < frame).max()
    }

    fn boundaries(&self) -> impl Iterator<Item = usize> + '_ {
        self.segments
            .iter()
            .flat_map(|s| [s.start, s.last_frame()])
            .chain(self.events.iter().map(|e| e.frame))
    }
}

/// The content of one labels file: a schema and the labels of each recording of a set.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LabelSet {
    /// The labels that may be used.
    pub schema: LabelSchema,
    /// Labels per recording, keyed by the recording's file name.
    pub recordings: BTreeMap<String, RecordingLabels>,
}

impl LabelSet {
    /// The labels of `recording`, if any were made.
    pub fn recording(&self, recording: &str) -> Option<&RecordingLabels> {
        self.recordings.get(recording)
    }

    /// The split of `recording`, if labelled.
    pub fn split_of(&self, recording: &str) -> Option<Split> {
        self.recording(recording).and_then(|r| r.meta.split)
    }

    /// Sorts, merges same-label neighbours and drops empty recordings, then checks every rule the
    /// editor keeps. Errors name the field (`recordings."a.csv".segments[2].label`) and the problem.
    pub fn normalise_and_validate(&mut self) -> Result<(), (String, String)> {
        self.schema
            .validate()
            .map_err(|(field, message)| (format!("schema.{field}"), message))?;
        self.recordings.retain(|_, r| !r.is_empty());
        for (name, rec) in &mut self.recordings {
            let at = |field: String| format!("recordings.{name:?}.{field}");
            rec.meta
                .validate()
                .map_err(|(field, message)| (at(format!("meta.{field}")), message))?;
            for (i, s) in rec.segments.iter().enumerate() {
                let field = |f: &str| at(format!("segments[{i}].{f}"));
                check_label(&self.schema, &s.label, LabelKind::Range)
                    .map_err(|message| (field("label"), message))?;
                if s.start >= s.end {
                    return Err((
                        field("end"),
                        format!(
                            "a segment must end after it starts (end is exclusive), found start {} and end {}",
                            s.start, s.end
                        ),
                    ));
                }
            }
            for (i, e) in rec.events.iter().enumerate() {
                check_label(&self.schema, &e.label, LabelKind::Event)
                    .map_err(|message| (at(format!("events[{i}].label")), message))?;
            }
            segments::merge_same_label(&mut rec.segments);
            segments::sort_events(&mut rec.events);
            if let Some((i, j)) = segments::find_exclusive_overlap(&rec.segments, &self.schema) {
                let (a, b) = (&rec.segments[i], &rec.segments[j]);
                return Err((
                    at("segments".into()),
                    format!(
                        "{:?} (frames {}..{}) and {:?} (frames {}..{}) overlap but are in the same exclusive group",
                        a.label, a.start, a.end, b.label, b.start, b.end
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks that `label` exists in `schema` and is of `kind`; the message says what was expected.
pub(crate) fn check_label(
    schema: &LabelSchema,
    label: &str,
    kind: LabelKind,
) -> Result<(), String> {
    let Some(def) = schema.get(label) else {
        let known: Vec<&str> = schema.labels.iter().map(|l| l.name.as_str()).collect();
        return Err(format!("unknown label {label:?}; the schema has {known:?}"));
    };
    if def.kind != kind {
        let (is, want) = match def.kind {
            LabelKind::Range => ("a range label", "a point event"),
            LabelKind::Event => ("a point event", "a range label"),
        };
        return Err(format!("{label:?} is {is}, expected {want} here"));
    }
    Ok(())
}
