//! Losses by label on the selected recording: the mean online and fixed loss over the frames each
//! label covers, e.g. how much worse the model predicts while slipping than while sticking, and how
//! much online learning helps in each. Uses the core's `PerLabelMeans`, as `pushlab eval` does.

use pushlab_core::labels::RecordingLabels;
use pushlab_core::labels::pipeline::PerLabelMeans;

use super::online::OnlineRun;

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
pub fn loss_by_label(run: &OnlineRun, labels: Option<&RecordingLabels>) -> Vec<LabelLoss> {
    let mut frames = Vec::new();
    let mut values = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
    for (frame, learned) in run.learned().iter().enumerate() {
        let (Some(online), Some(fixed)) = (learned, run.fixed().get(frame)) else {
            continue;
        };
        frames.push(frame);
        values[0].push(f64::from(online.pos));
        values[1].push(f64::from(fixed.pos));
        values[2].push(f64::from(online.rot));
        values[3].push(f64::from(fixed.rot));
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
    let mut rows = vec![row(&|m| Some((m.all().count, m.all().mean)), "all")];
    for label in means[0].by_label() {
        let name = label.label.clone();
        rows.push(row(
            &|m| m.get(&name).map(|l| (l.count, l.mean)),
            &label.label,
        ));
    }
    rows
}
