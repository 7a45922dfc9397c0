//! Exports of the labels for other tools: one row per segment or event, with frame numbers and the
//! recording's own frame times, as CSV or JSON.
//!
//! Unlike the labels file (half-open `start..end`), exports count frames the way people read a
//! table: `first_frame` and `last_frame` are both inclusive, and `first_time`/`last_time` are the
//! time stamps of those two frames, seconds, from the recording. A point event has
//! `first_frame == last_frame`.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::atomic_file::write_atomically;

use super::metadata::RecordingMeta;
use super::schema::LabelKind;
use super::{LabelSet, RecordingLabels};

/// The frame times of recordings, seconds, looked up by recording file name. Exports take this
/// instead of loading recordings themselves, so they work with any loader (and in tests).
pub trait FrameTimes {
    /// The time of every frame of `recording`, or `None` if it is not known.
    fn frame_times(&self, recording: &str) -> Option<&[f64]>;
}

impl FrameTimes for BTreeMap<String, Vec<f64>> {
    fn frame_times(&self, recording: &str) -> Option<&[f64]> {
        self.get(recording).map(Vec::as_slice)
    }
}

impl FrameTimes for HashMap<String, Vec<f64>> {
    fn frame_times(&self, recording: &str) -> Option<&[f64]> {
        self.get(recording).map(Vec::as_slice)
    }
}

/// One exported segment or event.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExportRow {
    /// Recording file name.
    pub recording: String,
    /// Label name.
    pub label: String,
    /// `range` or `event`.
    pub kind: LabelKind,
    /// First frame, inclusive.
    pub first_frame: usize,
    /// Last frame, inclusive.
    pub last_frame: usize,
    /// Time of `first_frame`, seconds.
    pub first_time: f64,
    /// Time of `last_frame`, seconds.
    pub last_time: f64,
}

/// Why an export failed.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// A labelled recording's frame times were not given.
    #[error(
        "cannot export labels of {recording}: its frame times are unknown (is the recording missing?)"
    )]
    MissingTimes { recording: String },
    /// A label lies beyond the recording's last frame.
    #[error(
        "cannot export labels of {recording}: {label:?} reaches frame {frame}, but the recording has {frames} frames (0 to {last})",
        last = frames.saturating_sub(1)
    )]
    BeyondEnd {
        recording: String,
        label: String,
        frame: usize,
        frames: usize,
    },
    /// Writing the export failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// The rows of all labelled recordings: recordings in name order, within each by first frame.
pub fn rows(set: &LabelSet, times: &impl FrameTimes) -> Result<Vec<ExportRow>, ExportError> {
    let mut out = Vec::new();
    for (name, labels) in &set.recordings {
        out.extend(recording_rows(name, labels, times)?);
    }
    Ok(out)
}

fn recording_rows(
    name: &str,
    labels: &RecordingLabels,
    times: &impl FrameTimes,
) -> Result<Vec<ExportRow>, ExportError> {
    if labels.segments.is_empty() && labels.events.is_empty() {
        return Ok(Vec::new());
    }
    let t = times
        .frame_times(name)
        .ok_or_else(|| ExportError::MissingTimes {
            recording: name.to_owned(),
        })?;
    let time = |label: &str, frame: usize| {
        t.get(frame).copied().ok_or_else(|| ExportError::BeyondEnd {
            recording: name.to_owned(),
            label: label.to_owned(),
            frame,
            frames: t.len(),
        })
    };
    let mut rows = Vec::with_capacity(labels.segments.len() + labels.events.len());
    for s in &labels.segments {
        rows.push(ExportRow {
            recording: name.to_owned(),
            label: s.label.clone(),
            kind: LabelKind::Range,
            first_frame: s.start,
            last_frame: s.last_frame(),
            first_time: time(&s.label, s.start)?,
            last_time: time(&s.label, s.last_frame())?,
        });
    }
    for e in &labels.events {
        let at = time(&e.label, e.frame)?;
        rows.push(ExportRow {
            recording: name.to_owned(),
            label: e.label.clone(),
            kind: LabelKind::Event,
            first_frame: e.frame,
            last_frame: e.frame,
            first_time: at,
            last_time: at,
        });
    }
    rows.sort_by(|a, b| {
        (a.first_frame, a.last_frame, &a.label).cmp(&(b.first_frame, b.last_frame, &b.label))
    });
    Ok(rows)
}

/// The CSV text: a header `recording,label,kind,first_frame,last_frame,first_time,last_time` and
/// one row per segment or event. Fields are quoted where CSV needs it.
pub fn to_csv(set: &LabelSet, times: &impl FrameTimes) -> Result<String, ExportError> {
    let mut text =
        String::from("recording,label,kind,first_frame,last_frame,first_time,last_time\n");
    for row in rows(set, times)? {
        let kind = match row.kind {
            LabelKind::Range => "range",
            LabelKind::Event => "event",
        };
        let fields = [
            quote(&row.recording),
            quote(&row.label),
            kind.to_owned(),
            row.first_frame.to_string(),
            row.last_frame.to_string(),
            row.first_time.to_string(),
            row.last_time.to_string(),
        ];
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    Ok(text)
}

/// Quotes a CSV field if it holds a comma, quote or line break (RFC 4180).
fn quote(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_owned()
    }
}

#[derive(Serialize)]
struct JsonExport<'a> {
    format: &'static str,
    version: u32,
    recordings: BTreeMap<&'a str, &'a RecordingMeta>,
    segments: Vec<ExportRow>,
}

/// The JSON text: `{"format": "pushlab-labels-export", "version": 1, "recordings": {name: meta},
/// "segments": [rows]}` with the same rows as the CSV.
pub fn to_json(set: &LabelSet, times: &impl FrameTimes) -> Result<String, ExportError> {
    let export = JsonExport {
        format: "pushlab-labels-export",
        version: 1,
        recordings: set
            .recordings
            .iter()
            .filter(|(_, r)| !r.meta.is_empty())
            .map(|(k, r)| (k.as_str(), &r.meta))
            .collect(),
        segments: rows(set, times)?,
    };
    // Only maps, strings and numbers from finite frame times: serialising cannot fail.
    let mut text = serde_json::to_string_pretty(&export).unwrap_or_default();
    text.push('\n');
    Ok(text)
}

/// Writes `text` to `path` atomically (an export never leaves a half-written file either).
pub fn write(path: &Path, text: &str) -> Result<(), ExportError> {
    write_atomically(path, text.as_bytes()).map_err(|source| ExportError::Write {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::super::file::tests::sample_set;
    use super::*;

    fn times() -> BTreeMap<String, Vec<f64>> {
        // 100 frames at 4 Hz starting at 1 s (exact in binary, so the expected text is readable);
        // push_001.csv has metadata only.
        let t: Vec<f64> = (0..100).map(|i| 1.0 + f64::from(i) * 0.25).collect();
        BTreeMap::from([("push_000.csv".to_owned(), t)])
    }

    #[test]
    fn csv_has_one_row_per_segment_and_event_with_times() {
        let csv = to_csv(&sample_set(), &times()).unwrap();
        let expected = "\
recording,label,kind,first_frame,last_frame,first_time,last_time
push_000.csv,contact made,event,3,3,1.75,1.75
push_000.csv,sticking,range,3,39,1.75,10.75
push_000.csv,contact,range,3,89,1.75,23.25
push_000.csv,slipping,range,40,89,11,23.25
push_000.csv,bad tracking,range,70,74,18.5,19.5
push_000.csv,contact lost,event,90,90,23.5,23.5
";
        assert_eq!(csv, expected);
    }

    #[test]
    fn csv_quotes_names_that_need_it() {
        let mut set = sample_set();
        let labels = set.recordings.remove("push_000.csv").unwrap();
        set.recordings.insert("run 1, \"fast\".csv".into(), labels);
        let t = BTreeMap::from([(
            "run 1, \"fast\".csv".to_owned(),
            times()["push_000.csv"].clone(),
        )]);
        let csv = to_csv(&set, &t).unwrap();
        assert!(
            csv.lines()
                .nth(1)
                .unwrap()
                .starts_with("\"run 1, \"\"fast\"\".csv\",contact made,event,3,3,")
        );
    }

    #[test]
    fn json_export_has_rows_and_metadata() {
        let json = to_json(&sample_set(), &times()).unwrap();
        let value: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(value["format"], "pushlab-labels-export");
        assert_eq!(value["segments"].as_array().unwrap().len(), 6);
        assert_eq!(value["segments"][3]["label"], "slipping");
        assert_eq!(value["segments"][3]["first_time"], 11.0);
        assert_eq!(value["recordings"]["push_001.csv"]["split"], "held-out");
        assert_eq!(value["recordings"]["push_000.csv"]["com_offset"][0], 0.0125);
    }

    #[test]
    fn missing_times_or_too_short_recordings_are_errors() {
        let err = to_csv(&sample_set(), &BTreeMap::new()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "cannot export labels of push_000.csv: its frame times are unknown (is the recording missing?)"
        );
        let short = BTreeMap::from([("push_000.csv".to_owned(), vec![0.0; 80])]);
        let err = to_csv(&sample_set(), &short).unwrap_err();
        assert_eq!(
            err.to_string(),
            "cannot export labels of push_000.csv: \"contact\" reaches frame 89, but the recording has 80 frames (0 to 79)"
        );
    }
}
