//! Frame-by-frame agreement of two labels files: how well proposals (or one person's labels) match a
//! reference such as the simulator's truth, per label, as precision, recall and F1.
//!
//! The reference decides what is judged: every recording it names, every frame of those, and every
//! range label of its schema. A frame counts for a label in a file when one of that label's segments
//! covers it; events are not compared. Recordings only the other file names are left out and
//! reported, so that proposals for more recordings than were labelled do not count as errors.

use serde::Serialize;

use super::{LabelKind, LabelSet, RecordingLabels};

/// The agreement on one label.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LabelAgreement {
    pub label: String,
    /// Of the frames the other file gives the label, the share the reference gives it too; `None`
    /// when the other file never gives it.
    pub precision: Option<f64>,
    /// Of the frames the reference gives the label, the share the other file gives it too; `None`
    /// when the reference never gives it.
    pub recall: Option<f64>,
    /// The harmonic mean of the two; `None` when neither file gives the label.
    pub f1: Option<f64>,
    /// Frames with the label in the reference.
    pub frames_truth: usize,
    /// Frames with the label in the other file.
    pub frames_other: usize,
}

/// The agreement on every label, and what was left out.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison {
    pub labels: Vec<LabelAgreement>,
    /// Recordings compared (those of the reference).
    #[serde(skip)]
    pub recordings: usize,
    /// Recordings only the other file has, not judged.
    #[serde(skip)]
    pub left_out: Vec<String>,
}

/// Why two files cannot be compared: scores over nothing would read as a result.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompareError {
    /// The reference labels no frame of any range label.
    #[error(
        "recordings: no frame of any range label, expected at least one labelled segment to compare against"
    )]
    EmptyReference,
    /// The other file labels none of the reference's recordings (likely another set).
    #[error(
        "recordings: none of the reference's recordings ({reference}) is labelled, found only {other}; were both files made for the same set?"
    )]
    NoSharedRecording { reference: String, other: String },
}

/// Compares `other` with the reference `truth`.
pub fn compare(truth: &LabelSet, other: &LabelSet) -> Result<Comparison, CompareError> {
    let has_segments = |set: &LabelSet| set.recordings.values().any(|r| !r.segments.is_empty());
    if !has_segments(truth) {
        return Err(CompareError::EmptyReference);
    }
    if !truth
        .recordings
        .keys()
        .any(|k| other.recordings.contains_key(k))
    {
        let list = |set: &LabelSet| {
            let names: Vec<&str> = set.recordings.keys().take(3).map(String::as_str).collect();
            let more = set.recordings.len().saturating_sub(3);
            match (names.is_empty(), more) {
                (true, _) => "no recording".to_owned(),
                (false, 0) => names.join(", "),
                (false, m) => format!("{} and {m} more", names.join(", ")),
            }
        };
        return Err(CompareError::NoSharedRecording {
            reference: list(truth),
            other: list(other),
        });
    }
    let empty = RecordingLabels::default();
    let labels = truth
        .schema
        .labels
        .iter()
        .filter(|l| l.kind == LabelKind::Range)
        .map(|def| {
            let (mut both, mut frames_truth, mut frames_other) = (0, 0, 0);
            for (name, reference) in &truth.recordings {
                let mine = other.recordings.get(name).unwrap_or(&empty);
                let a = frames_of(reference, &def.name);
                let b = frames_of(mine, &def.name);
                frames_truth += a.iter().map(|r| r.len()).sum::<usize>();
                frames_other += b.iter().map(|r| r.len()).sum::<usize>();
                both += overlap(&a, &b);
            }
            let ratio = |part: usize, whole: usize| (whole > 0).then(|| part as f64 / whole as f64);
            LabelAgreement {
                label: def.name.clone(),
                precision: ratio(both, frames_other),
                recall: ratio(both, frames_truth),
                f1: ratio(2 * both, frames_truth + frames_other),
                frames_truth,
                frames_other,
            }
        })
        .collect();
    Ok(Comparison {
        labels,
        recordings: truth.recordings.len(),
        left_out: other
            .recordings
            .keys()
            .filter(|k| !truth.recordings.contains_key(*k))
            .cloned()
            .collect(),
    })
}

/// The frame ranges of `label`, sorted (segments of one label never overlap).
fn frames_of(labels: &RecordingLabels, label: &str) -> Vec<std::ops::Range<usize>> {
    let mut ranges: Vec<_> = labels
        .segments
        .iter()
        .filter(|s| s.label == label)
        .map(|s| s.frames())
        .collect();
    ranges.sort_by_key(|r| r.start);
    ranges
}

/// Frames covered by both lists of sorted, disjoint ranges.
fn overlap(a: &[std::ops::Range<usize>], b: &[std::ops::Range<usize>]) -> usize {
    let (mut i, mut j, mut total) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        let start = a[i].start.max(b[j].start);
        let end = a[i].end.min(b[j].end);
        total += end.saturating_sub(start);
        if a[i].end <= b[j].end {
            i += 1;
        } else {
            j += 1;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::super::Segment;
    use super::super::schema::names::{CONTACT, NO_CONTACT, SLIPPING, STICKING};
    use super::*;

    fn set(recordings: &[(&str, Vec<Segment>)]) -> LabelSet {
        let mut set = LabelSet::default();
        for (name, segments) in recordings {
            set.recordings.insert(
                (*name).to_owned(),
                RecordingLabels {
                    segments: segments.clone(),
                    ..RecordingLabels::default()
                },
            );
        }
        set.normalise_and_validate().unwrap();
        set
    }

    #[test]
    fn precision_recall_and_f1_count_frames_per_label() {
        let truth = set(&[
            (
                "a.csv",
                vec![
                    Segment::new(NO_CONTACT, 0..10),
                    Segment::new(CONTACT, 10..100),
                    Segment::new(STICKING, 10..60),
                    Segment::new(SLIPPING, 60..100),
                ],
            ),
            ("b.csv", vec![Segment::new(CONTACT, 0..50)]),
        ]);
        let other = set(&[
            (
                "a.csv",
                vec![
                    Segment::new(NO_CONTACT, 0..5),
                    Segment::new(CONTACT, 5..100),
                    Segment::new(STICKING, 5..80),
                    Segment::new(SLIPPING, 80..100),
                ],
            ),
            // Not in the reference: left out, not counted against it.
            ("c.csv", vec![Segment::new(CONTACT, 0..1000)]),
        ]);
        let result = compare(&truth, &other).unwrap();
        let get = |name: &str| result.labels.iter().find(|l| l.label == name).unwrap();
        // Contact: 140 true frames (90 + 50), 95 proposed, of which 90 are true (5..10 is not).
        let contact = get(CONTACT);
        assert_eq!((contact.frames_truth, contact.frames_other), (140, 95));
        assert!((contact.precision.unwrap() - 90.0 / 95.0).abs() < 1e-12);
        assert!((contact.recall.unwrap() - 90.0 / 140.0).abs() < 1e-12);
        assert!((contact.f1.unwrap() - 180.0 / 235.0).abs() < 1e-12);
        // Sticking: 75 proposed, 50 of them true; slipping: 20 proposed, all true, of 40.
        let sticking = get(STICKING);
        assert!((sticking.precision.unwrap() - 50.0 / 75.0).abs() < 1e-12);
        assert_eq!(sticking.recall, Some(1.0));
        let slipping = get(SLIPPING);
        assert_eq!(slipping.precision, Some(1.0));
        assert_eq!(slipping.recall, Some(0.5));
        // A label neither file uses has no score at all, rather than a made-up 0 or 1.
        let bad = get("bad tracking");
        assert_eq!((bad.precision, bad.recall, bad.f1), (None, None, None));
        assert_eq!(result.left_out, vec!["c.csv".to_owned()]);
        assert_eq!(result.recordings, 2);
    }

    #[test]
    fn nothing_to_compare_is_an_error_not_a_score() {
        let truth = set(&[("a.csv", vec![Segment::new(CONTACT, 0..10)])]);
        assert_eq!(
            compare(&set(&[]), &truth),
            Err(CompareError::EmptyReference)
        );
        let other = set(&[
            ("b.csv", vec![Segment::new(CONTACT, 0..10)]),
            ("c.csv", vec![Segment::new(CONTACT, 0..10)]),
        ]);
        let err = compare(&truth, &other).unwrap_err();
        assert_eq!(
            err.to_string(),
            "recordings: none of the reference's recordings (a.csv) is labelled, found only b.csv, c.csv; were both files made for the same set?"
        );
    }
}
