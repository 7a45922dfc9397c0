//! What training and evaluation ask of the labels: which recordings belong to a split, which frames
//! to leave out, and per-label means of a per-frame value (loss while slipping vs. sticking).
//!
//! Nothing here knows the model: inputs are recording names, frame indices and plain `f64` series,
//! so `pushlab train`/`eval` and the app's training all use the same functions.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::file;
use super::metadata::Split;
use super::{LabelSet, RecordingLabels};
use crate::recording::bag::is_bag;
use crate::recording::dataset::is_dataset;
use crate::recording::is_recording_file;

/// The labels key of a recording file: its file name (`push_003.csv`), as used in the labels file
/// of its folder.
pub fn key_of(recording_path: &Path) -> Option<String> {
    recording_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
}

/// Whether `key` can be the labels key (see [`key_of`]) of a recording in `folder`: a recording
/// file there (a CSV, an MIT file; not the setting or the labels file beside them), or a push of a
/// bag or dataset there, whose source is the bag's or dataset's path, `#` and the push
/// (`run1.mcap#003`, `pusht#episode_000005`; the bag's name alone names none of its pushes).
pub fn key_names_a_recording_in(folder: &Path, key: &str) -> bool {
    if is_recording_file(&folder.join(key)) {
        return true;
    }
    key.split_once('#').is_some_and(|(file, push)| {
        let source = folder.join(file);
        !file.is_empty()
            && !push.is_empty()
            && crate::files::exists(&source)
            && (is_bag(&source) || is_dataset(&source))
    })
}

/// The labels file that describes the recording at `recording_path` (beside it).
pub fn labels_file_beside(recording_path: &Path) -> PathBuf {
    file::path_in(recording_path.parent().unwrap_or(Path::new(".")))
}

/// Names of the recordings labelled with `split`, sorted.
pub fn recordings_in_split(set: &LabelSet, split: Split) -> Vec<&str> {
    set.recordings
        .iter()
        .filter(|(_, r)| r.meta.split == Some(split))
        .map(|(name, _)| name.as_str())
        .collect()
}

/// One flag per frame: `true` where a label marked `skip_in_training` (`bad tracking`) covers the
/// frame. Labels past `frame_count` are ignored; an unlabelled recording skips nothing.
pub fn frames_to_skip(set: &LabelSet, recording: &str, frame_count: usize) -> Vec<bool> {
    let mut mask = vec![false; frame_count];
    let Some(labels) = set.recording(recording) else {
        return mask;
    };
    for segment in &labels.segments {
        if set
            .schema
            .get(&segment.label)
            .is_some_and(|l| l.skip_in_training)
        {
            let end = segment.end.min(frame_count);
            let start = segment.start.min(end);
            mask[start..end].fill(true);
        }
    }
    mask
}

/// The mean of a value over the frames carrying one label.
#[derive(Clone, Debug, PartialEq)]
pub struct LabelMean {
    /// Label name, or `"all"` for every value given.
    pub label: String,
    /// Number of values averaged.
    pub count: usize,
    /// Their mean (NaN when `count` is 0).
    pub mean: f64,
}

/// Why values could not be grouped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GroupError {
    /// Frame indices and values must pair up.
    #[error("{recording}: {frames} frame indices but {values} values; each value needs its frame")]
    LengthMismatch {
        recording: String,
        frames: usize,
        values: usize,
    },
}

/// Accumulates a per-frame value (a loss, an error) by range label over many recordings, to report
/// e.g. "mean loss while slipping 3.1 mm, while sticking 0.8 mm". A frame carrying several labels
/// (`contact` and `slipping`) counts for each. Non-finite values are counted apart, not averaged.
#[derive(Clone, Debug, Default)]
pub struct PerLabelMeans {
    sums: BTreeMap<String, (usize, f64)>,
    all: (usize, f64),
    non_finite: usize,
}

impl PerLabelMeans {
    /// Nothing accumulated yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `values[i]`, which belongs to frame `frames[i]` of `recording`, whose labels are
    /// `labels` (`None` if it has none).
    pub fn add(
        &mut self,
        recording: &str,
        labels: Option<&RecordingLabels>,
        frames: &[usize],
        values: &[f64],
    ) -> Result<(), GroupError> {
        if frames.len() != values.len() {
            return Err(GroupError::LengthMismatch {
                recording: recording.to_owned(),
                frames: frames.len(),
                values: values.len(),
            });
        }
        for (&frame, &value) in frames.iter().zip(values) {
            if !value.is_finite() {
                self.non_finite += 1;
                continue;
            }
            self.all.0 += 1;
            self.all.1 += value;
            for segment in labels.into_iter().flat_map(|l| l.segments_at(frame)) {
                let entry = self.sums.entry(segment.label.clone()).or_default();
                entry.0 += 1;
                entry.1 += value;
            }
        }
        Ok(())
    }

    /// The mean over every finite value added.
    pub fn all(&self) -> LabelMean {
        mean("all", self.all)
    }

    /// Per-label means, in label-name order, for labels that covered at least one value.
    pub fn by_label(&self) -> Vec<LabelMean> {
        self.sums
            .iter()
            .map(|(label, &acc)| mean(label, acc))
            .collect()
    }

    /// The mean for one label, if it covered any value.
    pub fn get(&self, label: &str) -> Option<LabelMean> {
        self.sums.get(label).map(|&acc| mean(label, acc))
    }

    /// How many values were NaN or infinite (left out of every mean).
    pub fn non_finite(&self) -> usize {
        self.non_finite
    }
}

fn mean(label: &str, (count, sum): (usize, f64)) -> LabelMean {
    LabelMean {
        label: label.to_owned(),
        count,
        mean: if count == 0 {
            f64::NAN
        } else {
            sum / count as f64
        },
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::super::file::tests::sample_set;
    use super::super::schema::names::*;
    use super::super::{RecordingMeta, Segment};
    use super::*;
    use crate::model::sample_is_skipped;

    #[test]
    fn a_key_names_a_recording_file_or_a_push_of_a_bag_not_any_file_of_the_folder() {
        let folder = std::env::temp_dir().join(format!("pushlab-keys-{}", std::process::id()));
        std::fs::create_dir_all(folder.join("rosbag")).unwrap();
        for name in [
            "push_003.csv",
            "motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.000_t=0.000.json",
            "setting.json",
            "pushlab-labels.json",
            "run1.mcap",
            "run1.pushlab-bag.json",
            "notes.txt",
            "rosbag/metadata.yaml",
        ] {
            std::fs::write(folder.join(name), "").unwrap();
        }
        let names = |key: &str| key_names_a_recording_in(&folder, key);
        assert!(names("push_003.csv"));
        assert!(names(
            "motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.000_t=0.000.json"
        ));
        assert!(names("run1.mcap#003"));
        assert!(names("rosbag#000"));
        // pushlab's own files, other files, a bag without its push, a push of a missing bag.
        for key in [
            "setting.json",
            "pushlab-labels.json",
            "run1.pushlab-bag.json",
            "notes.txt",
            "run1.mcap",
            "run1.mcap#",
            "run2.mcap#003",
            "push_004.csv",
            "#003",
        ] {
            assert!(!names(key), "{key:?} names no recording");
        }
        let _ = std::fs::remove_dir_all(&folder);
    }

    #[test]
    fn splits_select_recordings() {
        let mut set = sample_set();
        set.recordings.insert(
            "push_002.csv".into(),
            RecordingLabels {
                meta: RecordingMeta {
                    split: Some(Split::Offline),
                    ..Default::default()
                },
                ..Default::default()
            },
        );
        assert_eq!(
            recordings_in_split(&set, Split::Offline),
            vec!["push_000.csv", "push_002.csv"]
        );
        assert_eq!(
            recordings_in_split(&set, Split::HeldOut),
            vec!["push_001.csv"]
        );
        assert!(recordings_in_split(&set, Split::Online).is_empty());
    }

    #[test]
    fn bad_tracking_frames_are_skipped() {
        let set = sample_set();
        let mask = frames_to_skip(&set, "push_000.csv", 100);
        let skipped: Vec<usize> = (0..100).filter(|&i| mask[i]).collect();
        assert_eq!(skipped, vec![70, 71, 72, 73, 74]);
        // A shorter recording clips the label; an unlabelled one skips nothing.
        assert_eq!(
            frames_to_skip(&set, "push_000.csv", 72)
                .iter()
                .filter(|&&m| m)
                .count(),
            2
        );
        assert_eq!(frames_to_skip(&set, "unknown.csv", 10), vec![false; 10]);
        // A sample over `horizon` frames is skipped when its start or its end is.
        let skipped_starts: Vec<usize> = (0..100)
            .filter(|&k| sample_is_skipped(&mask, k, 10))
            .collect();
        assert_eq!(skipped_starts, [60, 61, 62, 63, 64, 70, 71, 72, 73, 74]);
        let horizon_1: Vec<usize> = (0..100)
            .filter(|&k| sample_is_skipped(&mask, k, 1))
            .collect();
        assert_eq!(horizon_1, [69, 70, 71, 72, 73, 74]);
        assert!(!sample_is_skipped(&mask, 99, 10), "past the mask's end");
    }

    #[test]
    fn per_label_means_separate_slipping_from_sticking() {
        let labels = RecordingLabels {
            segments: vec![
                Segment::new(CONTACT, 0..6),
                Segment::new(STICKING, 0..3),
                Segment::new(SLIPPING, 3..6),
            ],
            ..Default::default()
        };
        let mut means = PerLabelMeans::new();
        means
            .add(
                "a.csv",
                Some(&labels),
                &[0, 1, 2, 3, 4, 5, 6],
                &[1.0, 2.0, 3.0, 10.0, 20.0, f64::NAN, 7.0],
            )
            .unwrap();
        means.add("b.csv", None, &[0], &[4.0]).unwrap();
        assert_eq!(means.get(STICKING).unwrap().mean, 2.0);
        assert_eq!(
            means.get(SLIPPING).unwrap(),
            LabelMean {
                label: SLIPPING.into(),
                count: 2,
                mean: 15.0
            }
        );
        assert_eq!(means.get(CONTACT).unwrap().count, 5);
        assert_eq!(
            means.all(),
            LabelMean {
                label: "all".into(),
                count: 7,
                mean: 47.0 / 7.0
            }
        );
        assert_eq!(means.non_finite(), 1);
        assert_eq!(
            means
                .by_label()
                .iter()
                .map(|m| m.label.as_str())
                .collect::<Vec<_>>(),
            vec![CONTACT, SLIPPING, STICKING]
        );
        let err = means.add("c.csv", None, &[0, 1], &[1.0]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "c.csv: 2 frame indices but 1 values; each value needs its frame"
        );
    }
}
