//! Losses by label on the selected recording: the mean online and fixed loss over the frames each
//! label covers, e.g. how much worse the model predicts while slipping than while sticking, and how
//! much online learning helps in each. Uses the core's `PerLabelMeans`, as `pushlab eval` does.

use pushlab_core::labels::RecordingLabels;
use pushlab_core::labels::pipeline::PerLabelMeans;

use crate::app::state::learning::online::OnlineRun;

/// One row of the table: a label (or "all") and its mean losses.
#[derive(Clone, Debug, PartialEq)]
pub struct LabelLoss {
    pub label: String,
    /// Frames averaged: those learned so far that the label covers.
    pub frames: usize,
    /// Mean positional loss of the online-learned model (`(ℓ_pos,x + ℓ_pos,y) / 2`).
    pub online_pos: f64,
    /// Mean positional loss of the fixed model over the same frames.
    pub fixed_pos: f64,
    /// Mean rotational loss `ℓ_rot` of the online-learned model.
    pub online_rot: f64,
    /// Mean rotational loss of the fixed model over the same frames.
    pub fixed_rot: f64,
}

/// Mean losses per label over the frames the run has learned so far, "all" first. Online and fixed
/// are averaged over the same frames, so the two columns compare like with like.
///
/// Only the frames some label covers are walked (the Labels tab asks every frame, and a long
/// recording has a million learned frames); "all" is the run's running mean.
pub fn loss_by_label(run: &OnlineRun, labels: Option<&RecordingLabels>) -> Vec<LabelLoss> {
    let learned = run.learned();
    let mut covered: Vec<usize> = labels
        .into_iter()
        .flat_map(|l| &l.segments)
        .flat_map(|s| s.start.min(learned.len())..s.end.min(learned.len()))
        .collect();
    covered.sort_unstable();
    covered.dedup();
    let mut frames = Vec::new();
    let mut values = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
    for frame in covered {
        let (Some(online), Some(fixed)) = (learned[frame], run.fixed().get(frame)) else {
            continue;
        };
        frames.push(frame);
        values[0].push(online.pos);
        values[1].push(fixed.pos);
        values[2].push(online.rot);
        values[3].push(fixed.rot);
    }
    let means: Vec<PerLabelMeans> = values
        .iter()
        .map(|v| {
            let mut means = PerLabelMeans::new();
            // Frames and values are built pairwise above, so the lengths always match.
            let _ = means.add("", labels, &frames, v);
            means
        })
        .collect();
    let row = |pick: &dyn Fn(&PerLabelMeans) -> Option<(usize, f64)>, label: &str| {
        let get = |i: usize| pick(&means[i]).map_or((0, f64::NAN), |m| m);
        LabelLoss {
            label: label.to_owned(),
            frames: get(0).0,
            online_pos: get(0).1,
            fixed_pos: get(1).1,
            online_rot: get(2).1,
            fixed_rot: get(3).1,
        }
    };
    let all = run.mean_losses().unwrap_or_default();
    let mut rows = vec![LabelLoss {
        label: "all".to_owned(),
        frames: all.frames,
        online_pos: all.online_pos,
        fixed_pos: all.fixed_pos,
        online_rot: all.online_rot,
        fixed_rot: all.fixed_rot,
    }];
    for label in means[0].by_label() {
        let name = label.label.clone();
        rows.push(row(
            &|m| m.get(&name).map(|l| (l.count, l.mean)),
            &label.label,
        ));
    }
    rows
}
