//! What the plots draw of an online run: the per-step losses and their moving averages, fixed and
//! online, and `θ_online(t)`, each as a series over frames with a min/max [`Envelope`], so that a
//! plot asks for about two points per pixel column whatever the recording's length.
//!
//! The run keeps this up to date as it learns (`extend`) and when it forgets the future (`cut`), in
//! time proportional to what changed: the plots never walk a whole recording per frame.

use std::collections::VecDeque;

use pushlab_core::learn::{self, Spread};
use pushlab_core::model::{FrameLoss, OnlineParams};

use crate::app::state::learning::envelope::{Envelope, envelope_points};

/// Learned steps in the moving average of the loss plots.
pub const MOVING_AVERAGE: usize = 25;

/// Which loss of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LossPart {
    /// `(ℓ_pos,x + ℓ_pos,y) / 2`.
    Pos,
    /// `ℓ_rot`.
    Rot,
}

/// A series the plots draw, one value per frame (NaN: none at that frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Series {
    /// The fixed model's loss at every sample.
    Fixed(LossPart),
    /// Its trailing moving average over [`MOVING_AVERAGE`] samples.
    FixedAverage(LossPart),
    /// The online-learned model's loss where a step was learned.
    Online(LossPart),
    /// Its trailing moving average over the last [`MOVING_AVERAGE`] learned steps.
    OnlineAverage(LossPart),
    /// A component of `θ_online(t)` in millimetres: 0 the COM offset's x, 1 its y, 2 `h`.
    Theta(usize),
    /// The lower edge of its ±2σ band (the posterior's), millimetres.
    ThetaLow(usize),
    /// The upper edge.
    ThetaHigh(usize),
}

impl Series {
    const ALL: [Series; 17] = [
        Series::Fixed(LossPart::Pos),
        Series::Fixed(LossPart::Rot),
        Series::FixedAverage(LossPart::Pos),
        Series::FixedAverage(LossPart::Rot),
        Series::Online(LossPart::Pos),
        Series::Online(LossPart::Rot),
        Series::OnlineAverage(LossPart::Pos),
        Series::OnlineAverage(LossPart::Rot),
        Series::Theta(0),
        Series::Theta(1),
        Series::Theta(2),
        Series::ThetaLow(0),
        Series::ThetaLow(1),
        Series::ThetaLow(2),
        Series::ThetaHigh(0),
        Series::ThetaHigh(1),
        Series::ThetaHigh(2),
    ];

    fn index(self) -> usize {
        let part = |p: LossPart| usize::from(p == LossPart::Rot);
        match self {
            Series::Fixed(p) => part(p),
            Series::FixedAverage(p) => 2 + part(p),
            Series::Online(p) => 4 + part(p),
            Series::OnlineAverage(p) => 6 + part(p),
            Series::Theta(c) => 8 + c.min(2),
            Series::ThetaLow(c) => 11 + c.min(2),
            Series::ThetaHigh(c) => 14 + c.min(2),
        }
    }

    /// Whether online learning changes it (so steering cuts it back).
    fn follows_learning(self) -> bool {
        !matches!(self, Series::Fixed(_) | Series::FixedAverage(_))
    }

    fn len(self, data: &Data<'_>) -> usize {
        match self {
            Series::Fixed(_) | Series::FixedAverage(_) => data.fixed.len(),
            Series::Online(_) | Series::OnlineAverage(_) => data.learned.len(),
            Series::Theta(_) | Series::ThetaLow(_) | Series::ThetaHigh(_) => {
                data.checkpoints.len().min(data.spreads.len())
            }
        }
    }

    fn value(self, data: &Data<'_>, i: usize) -> f32 {
        let pick = |loss: PlotLoss, part: LossPart| match part {
            LossPart::Pos => loss.pos,
            LossPart::Rot => loss.rot,
        };
        match self {
            Series::Fixed(p) => pick(PlotLoss::of(&data.fixed[i]), p),
            Series::FixedAverage(p) => pick(data.averages.fixed[i], p),
            Series::Online(p) => data.learned[i].map_or(f32::NAN, |l| pick(PlotLoss::of(&l), p)),
            Series::OnlineAverage(p) => pick(data.averages.online[i], p),
            Series::Theta(c) => (data.checkpoints[i].to_array()[c.min(2)] * 1e3) as f32,
            Series::ThetaLow(c) | Series::ThetaHigh(c) => {
                let c = c.min(2);
                let sign = if matches!(self, Series::ThetaLow(_)) {
                    -2.0
                } else {
                    2.0
                };
                let value = data.checkpoints[i].to_array()[c] + sign * data.spreads[i].std()[c];
                (value * 1e3) as f32
            }
        }
    }
}

/// The run's series as the plots read them.
struct Data<'a> {
    fixed: &'a [FrameLoss],
    learned: &'a [Option<FrameLoss>],
    checkpoints: &'a [OnlineParams],
    spreads: &'a [Spread],
    averages: &'a Averages,
}

/// A loss as the plots draw it: in `f32`, half the memory of the run's for the averages kept per
/// frame.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PlotLoss {
    pos: f32,
    rot: f32,
}

impl PlotLoss {
    fn of(loss: &FrameLoss) -> Self {
        Self {
            pos: loss.pos as f32,
            rot: loss.rot as f32,
        }
    }
}

#[derive(Default)]
struct Averages {
    fixed: Vec<PlotLoss>,
    /// The running sums of the fixed losses over the last window, as the core's `moving_average`
    /// keeps them: a push that grows (a live one) extends the average with the same bits.
    fixed_sums: [f64; 2],
    /// One per learned frame; NaN where θ was held.
    online: Vec<PlotLoss>,
    /// The last [`MOVING_AVERAGE`] learned losses before the end of `online`.
    recent: VecDeque<PlotLoss>,
}

const NO_LOSS: PlotLoss = PlotLoss {
    pos: f32::NAN,
    rot: f32::NAN,
};

/// Moving averages and envelopes of one run's series.
pub struct RunPlots {
    averages: Averages,
    envelopes: [Envelope; 17],
}

impl RunPlots {
    /// The plots of a run that has learned nothing yet.
    pub(in crate::app::state) fn new(run: &mut learn::OnlineRun) -> Self {
        let mut plots = Self {
            averages: Averages::default(),
            envelopes: Default::default(),
        };
        run.take_cut();
        plots.extend(run.fixed(), &[], run.checkpoints(), run.spreads());
        plots
    }

    /// Follows the run: cuts back to the first frame it dropped since the last call, then adds what
    /// it learned.
    pub(in crate::app::state) fn follow(&mut self, run: &mut learn::OnlineRun) {
        if let Some(frame) = run.take_cut() {
            self.cut(run.learned(), frame);
        }
        self.extend(run.fixed(), run.learned(), run.checkpoints(), run.spreads());
    }

    /// Adds what the run learned since the last call.
    fn extend(
        &mut self,
        fixed: &[FrameLoss],
        learned: &[Option<FrameLoss>],
        checkpoints: &[OnlineParams],
        spreads: &[Spread],
    ) {
        let averages = &mut self.averages;
        for i in averages.fixed.len()..fixed.len() {
            let value = |i: usize| {
                let loss = PlotLoss::of(&fixed[i]);
                [f64::from(loss.pos), f64::from(loss.rot)]
            };
            let (now, sums) = (value(i), &mut averages.fixed_sums);
            for (c, sum) in sums.iter_mut().enumerate() {
                *sum += now[c];
                if i >= MOVING_AVERAGE {
                    *sum -= value(i - MOVING_AVERAGE)[c];
                }
            }
            let n = (i + 1).min(MOVING_AVERAGE) as f64;
            (averages.fixed).push(PlotLoss {
                pos: (sums[0] / n) as f32,
                rot: (sums[1] / n) as f32,
            });
        }
        for step in &learned[averages.online.len().min(learned.len())..] {
            let average = match step {
                Some(loss) => {
                    averages.recent.push_back(PlotLoss::of(loss));
                    if averages.recent.len() > MOVING_AVERAGE {
                        averages.recent.pop_front();
                    }
                    let n = averages.recent.len() as f32;
                    let sum = |pick: fn(&PlotLoss) -> f32| {
                        averages.recent.iter().map(pick).sum::<f32>() / n
                    };
                    PlotLoss {
                        pos: sum(|l| l.pos),
                        rot: sum(|l| l.rot),
                    }
                }
                None => NO_LOSS,
            };
            averages.online.push(average);
        }
        let data = Data {
            fixed,
            learned,
            checkpoints,
            spreads,
            averages: &self.averages,
        };
        for series in Series::ALL {
            self.envelopes[series.index()].extend(|i| series.value(&data, i), series.len(&data));
        }
    }

    /// Forgets what learning did from frame `frame` on (`learned` is already cut back to it): the
    /// online series and `θ` change there.
    fn cut(&mut self, learned: &[Option<FrameLoss>], frame: usize) {
        let averages = &mut self.averages;
        averages.online.truncate(frame.min(learned.len()));
        let mut recent: Vec<PlotLoss> = learned[..averages.online.len()]
            .iter()
            .rev()
            .flatten()
            .take(MOVING_AVERAGE)
            .map(PlotLoss::of)
            .collect();
        recent.reverse();
        averages.recent = recent.into();
        for series in Series::ALL.into_iter().filter(|s| s.follows_learning()) {
            self.envelopes[series.index()].truncate(frame);
        }
    }
}

impl RunPlots {
    /// The points to draw of `series` of `run` for the times `(x_min, x_max)` (seconds since the
    /// first frame) in a plot `columns` pixels wide: about two per column (see `envelope_points`).
    pub fn points(
        &self,
        run: &learn::OnlineRun,
        series: Series,
        visible: (f64, f64),
        columns: usize,
    ) -> Vec<[f64; 2]> {
        let frames = &run.trajectory().frames;
        let t0 = frames.first().map_or(0.0, |f| f.time);
        let data = Data {
            fixed: run.fixed(),
            learned: run.learned(),
            checkpoints: run.checkpoints(),
            spreads: run.spreads(),
            averages: &self.averages,
        };
        envelope_points(
            &self.envelopes[series.index()],
            |i| series.value(&data, i),
            |i| frames[i].time - t0,
            // θ at frame 0 is there before any frame is (a live push that has not begun).
            series.len(&data).min(frames.len()),
            visible,
            columns,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    use pushlab_core::learn::moving_average;

    use crate::app::state::learning::online::OnlineRun;

    use pushlab_core::geometry::{Outline, Pose2};
    use pushlab_core::learn::OnlineConfig;
    use pushlab_core::model::{LossScale, PhysicsOnlyModel, samples_from_trajectory};
    use pushlab_core::recording::{ObjectShape, Recording, Setting};
    use pushlab_core::trajectory::{Frame, Trajectory};

    /// Frame `i` of a 10 cm box pushed off-centre along +x at 100 Hz.
    fn frame(i: usize) -> Frame {
        let t = i as f64 * 0.01;
        let object = Pose2::new(0.05 * t, 0.0, 0.3 * t);
        let robot = object.point_in_world(nalgebra::Point2::new(-0.06, 0.01));
        Frame {
            time: t,
            robot,
            object,
        }
    }

    /// The push's first `n` frames.
    fn run(n: usize) -> OnlineRun {
        let frames = (0..n).map(frame).collect();
        let trajectory = Arc::new(Trajectory::new(frames));
        let mut scale = LossScale::from_samples(&samples_from_trajectory(&trajectory, 1));
        scale.sigma_pos = scale.sigma_pos.map(|s| s.max(1e-3));
        scale.sigma_rot = scale.sigma_rot.max(1e-3);
        let outline = Outline::rectangle(0.1, 0.1).expect("valid box");
        let model = PhysicsOnlyModel::new(outline, 0.01, 0.002, scale);
        let recording = Recording {
            source: "push.csv".into(),
            name: "push".into(),
            setting: Arc::new(Setting::of_object(
                "test",
                ObjectShape::Box {
                    width: 0.1,
                    length: 0.1,
                },
                0.01,
            )),
            entry: None,
            trajectory,
            warnings: Vec::new(),
            notes: Vec::new(),
            cameras: Vec::new(),
        };
        OnlineRun::new(
            Arc::new(model),
            &recording,
            1,
            OnlineConfig::default(),
            None,
        )
    }

    /// Every point `series` would give if the whole run were drawn point by point.
    fn all_points(run: &OnlineRun, series: Series) -> Vec<[f64; 2]> {
        run.plot_points(series, (-1.0, 1e9), usize::MAX / 4)
    }

    #[test]
    fn a_run_that_grows_as_frames_arrive_draws_what_the_whole_run_draws_to_the_bit() {
        // Before its first frame (a live push just connected) a run draws nothing.
        let empty = run(40);
        let mut grown = OnlineRun::new(
            Arc::clone(empty.model()),
            &Recording {
                trajectory: Arc::new(Trajectory::new(Vec::new())),
                ..empty.recording().clone()
            },
            1,
            OnlineConfig::default(),
            None,
        );
        for series in Series::ALL {
            assert_eq!(all_points(&grown, series), Vec::<[f64; 2]>::new());
        }
        let mut whole = run(300);
        whole.learn_through(0, 300, &[]);
        // A live push: frames arrive in batches and are learned as they come.
        for batch in [0..40, 40..41, 41..120, 120..300] {
            grown.extend(batch.map(frame).collect());
            let from = grown.frontier();
            grown.learn_through(from, grown.sample_count(), &[]);
        }
        for series in Series::ALL {
            assert_eq!(
                all_points(&grown, series),
                all_points(&whole, series),
                "{series:?}"
            );
        }
    }

    #[test]
    fn the_online_average_is_the_moving_average_of_the_learned_steps_after_steering_too() {
        let mut run = run(300);
        run.learn_through(0, 100, &[]);
        let mut skip = vec![false; 300];
        skip[120..130].fill(true);
        run.learn_through(100, 200, &skip);
        // Steer at 150: the future is forgotten and learned again from there.
        let steered = run.theta_at(150);
        run.set_theta_at(150, steered);
        run.learn_through(150, 250, &skip);

        let learned: Vec<f64> = run.learned().iter().flatten().map(|l| l.pos).collect();
        let expected = moving_average(&learned, MOVING_AVERAGE);
        let drawn: Vec<f64> = all_points(&run, Series::OnlineAverage(LossPart::Pos))
            .iter()
            .map(|p| p[1])
            .collect();
        assert_eq!(drawn.len(), expected.len());
        for (a, b) in drawn.iter().zip(&expected) {
            assert!((a - b).abs() <= 1e-6 * b.abs().max(1e-9), "{a} vs {b}");
        }
        // Held frames have no online point; θ has one per frame up to the frontier.
        assert_eq!(
            all_points(&run, Series::Online(LossPart::Rot)).len(),
            learned.len()
        );
        assert_eq!(
            all_points(&run, Series::Theta(2)).len(),
            run.checkpoints().len()
        );
    }

    #[test]
    fn envelopes_after_learning_and_steering_match_a_run_built_in_one_go() {
        let mut played = run(2000);
        for (from, to) in [(0, 333), (333, 1000), (1000, 1700)] {
            played.learn_through(from, to, &[]);
        }
        let mut steered = played.theta_at(500);
        steered.h *= 1.5;
        played.set_theta_at(500, steered);
        played.learn_through(500, 1700, &[]);

        let mut direct = run(2000);
        direct.learn_through(0, 500, &[]);
        direct.set_theta_at(500, steered);
        direct.learn_through(500, 1700, &[]);
        for series in Series::ALL {
            // 200 columns over 20 s: the envelope path, not point by point.
            let a = played.plot_points(series, (0.0, 20.0), 200);
            let b = direct.plot_points(series, (0.0, 20.0), 200);
            assert!(a.len() <= 400, "{series:?}: {} points", a.len());
            assert_eq!(a, b, "{series:?}");
        }
    }
}
