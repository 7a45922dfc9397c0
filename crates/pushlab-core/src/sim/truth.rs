//! The simulator's true contact and stick/slip per recorded frame, as a labels file: what a labeling
//! assist (or a person) is measured against.
//!
//! The simulator knows, for every integration substep, whether the pusher pressed on the object and
//! whether the contact slid ([`super::FrameContact`]); a frame takes the majority of the substeps
//! after it. Labels use the default schema's names — `contact` / `no contact` on every frame, and
//! `sticking` / `slipping` on the frames in contact — so that the file compares directly with
//! proposals or hand labels (`pushlab labels compare`).

use std::ops::Range;

use super::record::FrameContact;
use super::spec::GeneratedSet;
use crate::labels::schema::names::{CONTACT, NO_CONTACT, SLIPPING, STICKING};
use crate::labels::{LabelSet, RecordingLabels, Segment};

/// The file `pushlab simulate --truth-labels` writes into each set's folder.
pub const TRUTH_LABELS_FILE: &str = "truth-labels.json";

/// The true labels of every push of a generated set, keyed by the recordings' file names.
pub fn truth_labels(set: &GeneratedSet) -> LabelSet {
    let mut labels = LabelSet::default();
    for (entry, contacts) in set.setting.trajectories.iter().zip(&set.frame_contacts) {
        let recording = RecordingLabels {
            segments: truth_segments(contacts),
            ..RecordingLabels::default()
        };
        if !recording.is_empty() {
            labels.recordings.insert(entry.file.clone(), recording);
        }
    }
    labels
}

/// The segments of one push: contact or no contact on every frame, sticking or slipping where in
/// contact, sorted by start.
pub fn truth_segments(contacts: &[FrameContact]) -> Vec<Segment> {
    let contact = runs(contacts, |c| {
        Some(if c.in_contact() { CONTACT } else { NO_CONTACT })
    });
    let mode = runs(contacts, |c| {
        c.in_contact()
            .then_some(if c.slipping() { SLIPPING } else { STICKING })
    });
    let mut segments: Vec<Segment> = contact
        .into_iter()
        .chain(mode)
        .map(|(label, frames)| Segment::new(label, frames))
        .collect();
    crate::labels::segments::sort(&mut segments);
    segments
}

/// Maximal runs of frames with the same label (`None`: no label there).
fn runs(
    contacts: &[FrameContact],
    label: impl Fn(&FrameContact) -> Option<&'static str>,
) -> Vec<(&'static str, Range<usize>)> {
    let mut out: Vec<(&'static str, Range<usize>)> = Vec::new();
    for (frame, contact) in contacts.iter().enumerate() {
        let Some(name) = label(contact) else {
            continue;
        };
        match out.last_mut() {
            Some((last, frames)) if *last == name && frames.end == frame => frames.end = frame + 1,
            _ => out.push((name, frame..frame + 1)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn frame(pressing: u32, sliding: u32) -> FrameContact {
        FrameContact {
            substeps: 10,
            pressing,
            sliding,
        }
    }

    #[test]
    fn a_frame_takes_the_majority_of_its_substeps() {
        let contacts = [
            frame(0, 0),
            frame(5, 0),
            frame(6, 0),
            frame(10, 6),
            frame(10, 5),
            frame(10, 9),
        ];
        let segments = truth_segments(&contacts);
        assert_eq!(
            segments,
            vec![
                Segment::new(NO_CONTACT, 0..2),
                Segment::new(CONTACT, 2..6),
                Segment::new(STICKING, 2..3),
                Segment::new(SLIPPING, 3..4),
                Segment::new(STICKING, 4..5),
                Segment::new(SLIPPING, 5..6),
            ]
        );
        // The labels pass every rule a labels file keeps (exclusive groups, sorted, non-empty).
        let mut set = LabelSet::default();
        set.recordings.insert(
            "push_000.csv".into(),
            RecordingLabels {
                segments,
                ..RecordingLabels::default()
            },
        );
        set.normalise_and_validate().unwrap();
    }
}
