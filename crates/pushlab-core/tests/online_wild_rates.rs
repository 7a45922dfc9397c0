//! One rule for a non-finite online step, for every model kind (`paper`, `contact`, physics only):
//! a step that would make `θ_online` non-finite is not taken, so that no `θ` and no loss shown or
//! reported is ever NaN or infinite — checked with learning rates of 10 and 10⁶ on the real MIT
//! pushes in `../shared/mit-push/` (skipped with a message when absent).

use crate::skip;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use std::sync::Arc;

use pushlab_core::experiment::{self, UsedRecording, model_on, online_run, physics_model};
use pushlab_core::learn::{OnlineConfig, TrainConfig};
use pushlab_core::model::{DEFAULT_CONTACT_TOLERANCE, ModelKind, OnlineStep, SharedOnlineModel};

/// The horizon of the MIT suites (`experiments/mit-abs-leave-one-shape-out.json`).
const HORIZON: usize = 10;

fn mit_dir() -> Option<PathBuf> {
    skip::shared(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        "mit-push",
    )
}

/// Every number of a step that a plot, the Inspect tab or a report shows is finite.
fn assert_finite(step: &OnlineStep, what: &str) {
    let theta = [step.theta_before, step.theta_after];
    assert!(
        theta
            .iter()
            .all(|t| t.com_offset.iter().all(|c| c.is_finite()) && t.h.is_finite()),
        "{what}: θ {theta:?}"
    );
    let loss = step.loss;
    assert!(
        [loss.pos_x, loss.pos_y, loss.rot]
            .iter()
            .all(|l| l.is_finite()),
        "{what}: loss {loss:?} at θ {:?}",
        step.theta_before
    );
    assert!(
        step.gradient.iter().all(|g| g.is_finite()),
        "{what}: gradient {:?} at θ {:?}",
        step.gradient,
        step.theta_before
    );
}

/// Online learning at `lr` along every push (the run `pushlab eval` and the app play), for one
/// model per push: θ, the losses and the gradient at every frame, online and fixed.
fn check_rates(
    name: &str,
    used: &[UsedRecording],
    model: impl Fn(&UsedRecording) -> SharedOnlineModel,
) {
    for u in used {
        for lr in [10.0, 1e6] {
            let config = OnlineConfig {
                steps: 5,
                lr,
                ..OnlineConfig::default()
            };
            let run = online_run(model(u), u, HORIZON, &config, None);
            assert_eq!(run.frontier(), run.sample_count(), "learned to the end");
            for k in 0..run.sample_count() {
                let at = format!("{name} at lr {lr} on {} frame {k}", u.source());
                assert_finite(&run.evaluate(k).expect("a sample"), &at);
                assert_finite(&run.evaluate_fixed(k).expect("a sample"), &at);
                assert!(run.spread_at(k).std().iter().all(|s| s.is_finite()), "{at}");
            }
        }
    }
}

#[test]
fn no_kind_ever_learns_a_non_finite_theta_or_loss_on_real_pushes_at_lr_10_and_1e6() {
    let Some(dir) = mit_dir() else { return };
    let loaded = experiment::load(std::slice::from_ref(&dir), None, HORIZON);
    assert_eq!(loaded.used.len(), 4, "{:?}", loaded.skipped);
    let config = TrainConfig {
        epochs: 2,
        horizon: HORIZON,
        ..TrainConfig::default()
    };
    let no = AtomicBool::new(false);
    for kind in ModelKind::ALL {
        let model = experiment::train_combined(kind, &loaded.used, &config, &mut |_| {}, &no)
            .expect("trains")
            .model;
        check_rates(kind.name(), &loaded.used, |u| {
            model_on(&model, u).expect("every MIT object has an outline")
        });
        if kind == ModelKind::Contact {
            let scale = model.loss_scale();
            check_rates("physics only", &loaded.used, |u| {
                Arc::new(
                    physics_model(&u.recording, scale, DEFAULT_CONTACT_TOLERANCE)
                        .expect("every MIT object has an outline"),
                )
            });
        }
    }
}
