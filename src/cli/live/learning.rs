//! `pushlab live --setting SETTING.json`: θ learned online as the frames arrive, by the core
//! [`LiveLearner`] (the grid a bag import makes, the run `eval` makes), and what the line of each
//! second says of it: θ, its σ, and the mean online and fixed losses over the frames learned.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::anyhow;
use clap::Args;
use pushlab_core::live::{LiveLearner, Stream};
use pushlab_core::recording::bag::PlanarPose;
use pushlab_core::recording::bag::SettingSource;
use serde_json::json;

use crate::cli::exit::Failure;
use crate::cli::experiment::args::OnlineArgs;
use crate::cli::import::rate;
use crate::cli::model_arg::load_model;

/// How `pushlab live` learns, if it does.
#[derive(Debug, Args)]
pub struct LearningArgs {
    /// Learn θ online as the frames arrive, on the object and pusher this setting.json gives (as
    /// `pushlab import --setting`).
    #[arg(long, value_name = "SETTING.json")]
    pub setting: Option<PathBuf>,
    /// With --setting: the model to learn with (default: the app's, assets/default-model.json).
    #[arg(long, value_name = "MODEL.json", requires = "setting")]
    pub model: Option<PathBuf>,
    /// With --setting: the grid's rate, Hz (default: the rate the model was trained at).
    #[arg(long, value_name = "HZ", value_parser = rate, requires = "setting")]
    pub rate: Option<f64>,
    // With --setting: how θ learns, as in `pushlab eval`.
    #[command(flatten)]
    pub online: OnlineArgs,
}

/// Learning along a live session, and what it says.
pub(super) struct Learning {
    learner: LiveLearner,
    /// Time spent learning since the last line.
    busy: Duration,
    /// Whether a refused pose was said already.
    said_refused: bool,
    said_full: bool,
}

impl Learning {
    /// Learning as `args` ask, or `None` without `--setting`.
    pub(super) fn new(args: &LearningArgs) -> Result<Option<Self>, Failure> {
        let Some(setting_path) = &args.setting else {
            return Ok(None);
        };
        let setting = SettingSource::File(setting_path.clone())
            .resolve()
            .map_err(|e| Failure::Failed(anyhow!("{e}")))?;
        let (model, model_name) = load_model(args.model.as_deref())?;
        let rate = match args.rate {
            Some(rate) => rate,
            None => (model.training.domain.as_ref())
                .and_then(|d| d.single_rate_hz())
                .ok_or_else(|| {
                    Failure::Usage(anyhow!(
                        "{model_name} does not say the one frame rate it was trained at: give --rate HZ"
                    ))
                })?,
        };
        let config = args.online.config();
        let learner = LiveLearner::new(&model.combined, &setting, config, rate)
            .map_err(|e| Failure::Usage(anyhow!("{}: {e}", setting_path.display())))?;
        println!(
            "learning θ online with {model_name} (horizon {} frames) on a {rate} Hz grid; replay: pushlab import --rate {rate}",
            model.combined.horizon()
        );
        Ok(Some(Self {
            learner,
            busy: Duration::ZERO,
            said_refused: false,
            said_full: false,
        }))
    }

    /// Takes a pose that arrived; a refused one is said the first time.
    pub(super) fn take(&mut self, stream: Stream, pose: &PlanarPose, log_time_ns: u64) {
        if let Err(refused) = self.learner.take(stream, pose, log_time_ns)
            && !self.said_refused
        {
            self.said_refused = true;
            eprintln!(
                "warning: a pose left out of learning (and every such pose after it, counted): {refused}"
            );
        }
    }

    /// Learns from the frames that became final.
    pub(super) fn learn(&mut self) {
        let started = Instant::now();
        self.learner.learn();
        self.busy += started.elapsed();
        if self.learner.grid().is_full() && !self.said_full {
            self.said_full = true;
            eprintln!(
                "warning: the push reached the longest an import takes; learning stopped (the recording goes on)"
            );
        }
    }

    /// The text of the line of a second.
    pub(super) fn text(&mut self) -> String {
        let run = self.learner.run();
        let frames = self.learner.grid().frames();
        let busy = std::mem::take(&mut self.busy);
        if run.frontier() == 0 {
            return format!("learning: {frames} frame(s), none learned yet");
        }
        let theta = run.theta_at(run.frontier());
        let [sx, sy, sh] = run.spread_at(run.frontier()).std();
        let mm = 1e3;
        let mut text = format!(
            "θ COM ({:.1}, {:.1}) ± ({:.1}, {:.1}) mm, h {:.1} ± {:.1} mm, {} frame(s) learned",
            theta.com_offset[0] * mm,
            theta.com_offset[1] * mm,
            sx * mm,
            sy * mm,
            theta.h * mm,
            sh * mm,
            run.frontier(),
        );
        if let Some(m) = run.mean_losses() {
            text += &format!(
                ", loss online {:.3}/{:.3} fixed {:.3}/{:.3}",
                m.online_pos, m.online_rot, m.fixed_pos, m.fixed_rot
            );
        }
        if let Some((frame, pose)) = self.learner.ahead() {
            let score = self.learner.ahead_score();
            text += &format!(
                "; ahead to frame {frame}: object at ({:.3}, {:.3}) m {:.1}°",
                pose.position.x,
                pose.position.y,
                pose.yaw.to_degrees()
            );
            if score.predictions > 0 {
                text += &format!(
                    " (such predictions off by {:.1} mm, {:.1}° on average over {}; the object's last motion repeated: {:.1} mm, {:.1}°)",
                    score.mean_position_m * mm,
                    score.mean_yaw_rad.to_degrees(),
                    score.predictions,
                    score.baseline_position_m * mm,
                    score.baseline_yaw_rad.to_degrees(),
                );
            }
        }
        text + &format!(" ({:.1} ms learning)", busy.as_secs_f64() * 1e3)
    }

    /// The same as JSON.
    pub(super) fn json(&mut self) -> serde_json::Value {
        let run = self.learner.run();
        let frontier = run.frontier();
        let busy = std::mem::take(&mut self.busy);
        let theta = run.theta_at(frontier);
        let [sx, sy, sh] = run.spread_at(frontier).std();
        let refused = self.learner.refused();
        json!({
            "frames": self.learner.grid().frames(),
            "frontier": frontier,
            "theta": {"com_offset": theta.com_offset, "h": theta.h},
            "sigma": {"com_offset": [sx, sy], "h": sh},
            "mean_losses": run.mean_losses().map(|m| json!({
                "frames": m.frames,
                "online_pos": m.online_pos, "online_rot": m.online_rot,
                "fixed_pos": m.fixed_pos, "fixed_rot": m.fixed_rot,
            })),
            "refused": {"out_of_order": refused.out_of_order, "bad_value": refused.bad_value},
            "ahead": self.learner.ahead().map(|(frame, pose)| {
                let score = self.learner.ahead_score();
                json!({"frame": frame, "x": pose.position.x, "y": pose.position.y, "yaw": pose.yaw,
                       "scored": score.predictions, "mean_position_m": score.mean_position_m,
                       "mean_yaw_rad": score.mean_yaw_rad,
                       "baseline_position_m": score.baseline_position_m,
                       "baseline_yaw_rad": score.baseline_yaw_rad})
            }),
            "learning_ms": busy.as_secs_f64() * 1e3,
        })
    }
}
