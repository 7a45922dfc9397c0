//! Per-frame labels: range segments and point events, and the painting rules that keep them tidy.
//!
//! **Frame ranges are half-open**: a segment with `start: 10, end: 20` covers frames 10 to 19, so
//! `end − start` is its length in frames, adjacent segments share a boundary number, and an empty
//! range cannot be written. Frame indices count from 0 in the recording's frame order.
//!
//! Invariants kept by [`paint`] and [`erase`] (and checked when a file is loaded):
//! - segments are non-empty and sorted by start;
//! - two segments of the same label never overlap or touch (they are merged);
//! - two labels of one exclusive group never cover the same frame (painting one cuts the other).

use std::ops::Range;

use serde::{Deserialize, Serialize};

use super::schema::LabelSchema;

/// A range label over frames `start..end` (half-open).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Segment {
    /// The label's name in the schema.
    pub label: String,
    /// First frame covered.
    pub start: usize,
    /// One past the last frame covered.
    pub end: usize,
}

impl Segment {
    /// A segment of `label` over `frames`.
    pub fn new(label: &str, frames: Range<usize>) -> Self {
        Self {
            label: label.to_owned(),
            start: frames.start,
            end: frames.end,
        }
    }

    /// The frames it covers.
    pub fn frames(&self) -> Range<usize> {
        self.start..self.end
    }

    /// Whether it covers `frame`.
    pub fn contains(&self, frame: usize) -> bool {
        self.frames().contains(&frame)
    }

    /// The last frame it covers (inclusive), as exports and people count.
    pub fn last_frame(&self) -> usize {
        self.end.saturating_sub(1)
    }

    fn overlaps(&self, frames: &Range<usize>) -> bool {
        self.start < frames.end && frames.start < self.end
    }

    fn touches(&self, frames: &Range<usize>) -> bool {
        self.start <= frames.end && frames.start <= self.end
    }
}

/// A point event at one frame.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Event {
    /// The label's name in the schema.
    pub label: String,
    /// The frame it marks.
    pub frame: usize,
}

/// Paints `label` over `frames`: cuts the parts of other labels of its exclusive group that lie
/// under `frames`, and merges with segments of the same label that overlap or touch it. An empty
/// range changes nothing.
pub fn paint(segments: &mut Vec<Segment>, schema: &LabelSchema, label: &str, frames: Range<usize>) {
    if frames.is_empty() {
        return;
    }
    let mut merged = frames.clone();
    let mut kept = Vec::with_capacity(segments.len() + 2);
    for segment in segments.drain(..) {
        if segment.label == label {
            if segment.touches(&merged) {
                merged = merged.start.min(segment.start)..merged.end.max(segment.end);
            } else {
                kept.push(segment);
            }
        } else if schema.excludes(&segment.label, label) && segment.overlaps(&frames) {
            kept.extend(cut(&segment, &frames));
        } else {
            kept.push(segment);
        }
    }
    // A segment of the same label found before the range grew may touch the grown range: merge again.
    kept.retain(|s| {
        if s.label == label && s.touches(&merged) {
            merged = merged.start.min(s.start)..merged.end.max(s.end);
            false
        } else {
            true
        }
    });
    kept.push(Segment::new(label, merged));
    sort(&mut kept);
    *segments = kept;
}

/// Removes `label` (or, with `None`, every range label) from `frames`, cutting segments that
/// extend beyond the range.
pub fn erase(segments: &mut Vec<Segment>, label: Option<&str>, frames: Range<usize>) {
    if frames.is_empty() {
        return;
    }
    let mut kept = Vec::with_capacity(segments.len() + 1);
    for segment in segments.drain(..) {
        let selected = label.is_none_or(|l| l == segment.label);
        if selected && segment.overlaps(&frames) {
            kept.extend(cut(&segment, &frames));
        } else {
            kept.push(segment);
        }
    }
    sort(&mut kept);
    *segments = kept;
}

/// The parts of `segment` outside `frames` (zero, one or two segments).
fn cut(segment: &Segment, frames: &Range<usize>) -> impl Iterator<Item = Segment> {
    let before = Segment::new(&segment.label, segment.start..frames.start.min(segment.end));
    let after = Segment::new(&segment.label, frames.end.max(segment.start)..segment.end);
    [before, after].into_iter().filter(|s| s.start < s.end)
}

/// Sorts segments by start, then label, then end: a stable order for files, diffs and the UI.
pub fn sort(segments: &mut [Segment]) {
    segments.sort_by(|a, b| (a.start, &a.label, a.end).cmp(&(b.start, &b.label, b.end)));
}

/// Sorts events by frame then label and drops exact duplicates.
pub fn sort_events(events: &mut Vec<Event>) {
    events.sort_by(|a, b| (a.frame, &a.label).cmp(&(b.frame, &b.label)));
    events.dedup();
}

/// Merges overlapping or touching segments of the same label and sorts, as [`paint`] would have
/// left them. Used on segments read from a file, which a person may have edited by hand.
pub fn merge_same_label(segments: &mut Vec<Segment>) {
    sort(segments);
    let mut merged: Vec<Segment> = Vec::with_capacity(segments.len());
    for segment in segments.drain(..) {
        let frames = segment.frames();
        match merged
            .iter_mut()
            .rev()
            .find(|m| m.label == segment.label && m.touches(&frames))
        {
            Some(m) => m.end = m.end.max(segment.end),
            None => merged.push(segment),
        }
    }
    *segments = merged;
}

/// The first pair of segments (by index) whose labels exclude each other and that share a frame.
pub fn find_exclusive_overlap(
    segments: &[Segment],
    schema: &LabelSchema,
) -> Option<(usize, usize)> {
    for (i, a) in segments.iter().enumerate() {
        for (j, b) in segments.iter().enumerate().skip(i + 1) {
            if schema.excludes(&a.label, &b.label) && a.overlaps(&b.frames()) {
                return Some((i, j));
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::collections::BTreeSet;

    use super::super::schema::names::*;
    use super::*;

    fn seg(label: &str, start: usize, end: usize) -> Segment {
        Segment::new(label, start..end)
    }

    fn painted(steps: &[(&str, usize, usize)]) -> Vec<Segment> {
        let schema = LabelSchema::default();
        let mut segments = Vec::new();
        for &(label, start, end) in steps {
            paint(&mut segments, &schema, label, start..end);
        }
        segments
    }

    #[test]
    fn slipping_inside_sticking_cuts_it_in_two() {
        let s = painted(&[(STICKING, 0, 100), (SLIPPING, 40, 60)]);
        assert_eq!(
            s,
            vec![
                seg(STICKING, 0, 40),
                seg(SLIPPING, 40, 60),
                seg(STICKING, 60, 100)
            ]
        );
    }

    #[test]
    fn slipping_over_the_start_or_end_of_sticking_trims_it() {
        assert_eq!(
            painted(&[(STICKING, 10, 50), (SLIPPING, 0, 20)]),
            vec![seg(SLIPPING, 0, 20), seg(STICKING, 20, 50)]
        );
        assert_eq!(
            painted(&[(STICKING, 10, 50), (SLIPPING, 40, 70)]),
            vec![seg(STICKING, 10, 40), seg(SLIPPING, 40, 70)]
        );
    }

    #[test]
    fn covering_a_segment_entirely_removes_it() {
        assert_eq!(
            painted(&[(STICKING, 10, 20), (STICKING, 30, 40), (SLIPPING, 5, 45)]),
            vec![seg(SLIPPING, 5, 45)]
        );
        // Exactly the same range.
        assert_eq!(
            painted(&[(STICKING, 10, 20), (SLIPPING, 10, 20)]),
            vec![seg(SLIPPING, 10, 20)]
        );
    }

    #[test]
    fn labels_of_other_groups_are_untouched() {
        assert_eq!(
            painted(&[
                (STICKING, 0, 50),
                (CONTACT, 0, 50),
                (BAD_TRACKING, 10, 20),
                (SLIPPING, 5, 30)
            ]),
            vec![
                seg(CONTACT, 0, 50),
                seg(STICKING, 0, 5),
                seg(SLIPPING, 5, 30),
                seg(BAD_TRACKING, 10, 20),
                seg(STICKING, 30, 50),
            ]
        );
    }

    #[test]
    fn same_label_overlapping_or_adjacent_merges() {
        assert_eq!(
            painted(&[(STICKING, 0, 10), (STICKING, 5, 20)]),
            vec![seg(STICKING, 0, 20)]
        );
        // Touching at the boundary (half-open): 0..10 and 10..20 become 0..20.
        assert_eq!(
            painted(&[(STICKING, 0, 10), (STICKING, 10, 20)]),
            vec![seg(STICKING, 0, 20)]
        );
        // A gap of one frame stays a gap.
        assert_eq!(
            painted(&[(STICKING, 0, 10), (STICKING, 11, 20)]),
            vec![seg(STICKING, 0, 10), seg(STICKING, 11, 20)]
        );
        // Bridging two segments merges all three.
        assert_eq!(
            painted(&[(STICKING, 0, 10), (STICKING, 20, 30), (STICKING, 10, 20)]),
            vec![seg(STICKING, 0, 30)]
        );
        // Painting inside an existing segment changes nothing.
        assert_eq!(
            painted(&[(STICKING, 0, 30), (STICKING, 5, 6)]),
            vec![seg(STICKING, 0, 30)]
        );
    }

    #[test]
    fn painting_between_two_slips_with_sticking_then_slipping_again_rejoins() {
        let s = painted(&[(SLIPPING, 0, 30), (STICKING, 10, 20), (SLIPPING, 10, 20)]);
        assert_eq!(s, vec![seg(SLIPPING, 0, 30)]);
    }

    #[test]
    fn empty_range_changes_nothing() {
        assert_eq!(
            painted(&[(STICKING, 0, 10), (SLIPPING, 5, 5)]),
            vec![seg(STICKING, 0, 10)]
        );
    }

    #[test]
    fn erase_cuts_only_the_chosen_label() {
        let mut s = painted(&[(STICKING, 0, 50), (BAD_TRACKING, 0, 50)]);
        erase(&mut s, Some(STICKING), 10..20);
        assert_eq!(
            s,
            vec![
                seg(BAD_TRACKING, 0, 50),
                seg(STICKING, 0, 10),
                seg(STICKING, 20, 50)
            ]
        );
        erase(&mut s, None, 0..15);
        assert_eq!(s, vec![seg(BAD_TRACKING, 15, 50), seg(STICKING, 20, 50)]);
    }

    #[test]
    fn merge_same_label_tidies_hand_written_segments() {
        let mut s = vec![
            seg(STICKING, 20, 30),
            seg(STICKING, 0, 10),
            seg(STICKING, 5, 20),
        ];
        merge_same_label(&mut s);
        assert_eq!(s, vec![seg(STICKING, 0, 30)]);
    }

    #[test]
    fn exclusive_overlap_is_found() {
        let schema = LabelSchema::default();
        let s = vec![
            seg(STICKING, 0, 10),
            seg(CONTACT, 0, 10),
            seg(SLIPPING, 9, 12),
        ];
        assert_eq!(find_exclusive_overlap(&s, &schema), Some((0, 2)));
        let s = vec![seg(STICKING, 0, 10), seg(SLIPPING, 10, 12)];
        assert_eq!(find_exclusive_overlap(&s, &schema), None);
    }

    /// A tiny deterministic generator, so the randomised test needs no extra dependency.
    struct SplitMix(u64);
    impl SplitMix {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        }
        fn below(&mut self, n: u64) -> usize {
            (self.next() % n) as usize
        }
    }

    /// Maximal runs of each label in a per-frame reference, in `sort` order.
    fn runs(frames: &[BTreeSet<&str>]) -> Vec<Segment> {
        let labels: BTreeSet<&str> = frames.iter().flatten().copied().collect();
        let mut out = Vec::new();
        for label in labels {
            let mut start = None;
            for (i, set) in frames.iter().chain([&BTreeSet::new()]).enumerate() {
                match (set.contains(label), start) {
                    (true, None) => start = Some(i),
                    (false, Some(s)) => {
                        out.push(seg(label, s, i));
                        start = None;
                    }
                    _ => {}
                }
            }
        }
        sort(&mut out);
        out
    }

    /// Random paint and erase sequences agree with a frame-by-frame reference: each frame holds a
    /// set of labels, and painting a label removes the others of its group from those frames.
    #[test]
    fn random_edits_match_a_per_frame_reference() {
        let schema = LabelSchema::default();
        let labels = [CONTACT, NO_CONTACT, STICKING, SLIPPING, BAD_TRACKING];
        let n = 40;
        let mut rng = SplitMix(7);
        for _ in 0..300 {
            let mut segments = Vec::new();
            let mut reference: Vec<BTreeSet<&str>> = vec![BTreeSet::new(); n];
            for _ in 0..12 {
                let a = rng.below(n as u64);
                let b = rng.below(n as u64 + 1);
                let frames = a.min(b)..a.max(b);
                let label = labels[rng.below(labels.len() as u64)];
                if rng.below(5) == 0 {
                    let which = (rng.below(2) == 0).then_some(label);
                    erase(&mut segments, which, frames.clone());
                    for set in &mut reference[frames] {
                        match which {
                            Some(l) => {
                                set.remove(l);
                            }
                            None => set.clear(),
                        }
                    }
                } else {
                    paint(&mut segments, &schema, label, frames.clone());
                    for set in &mut reference[frames] {
                        set.retain(|other| !schema.excludes(other, label));
                        set.insert(label);
                    }
                }
                assert_eq!(segments, runs(&reference));
                assert_eq!(find_exclusive_overlap(&segments, &schema), None);
            }
        }
    }
}
