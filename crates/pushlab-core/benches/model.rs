//! Speed of the models: one prediction, one online step (predict + 5 gradient steps) and one epoch of
//! offline training. Run with `cargo bench -p pushlab-core --bench model`.
//!
//! - `predict`, `online_step`: the contact-frame model (the default kind) on a box;
//! - `predict_64gon`, `online_step_64gon`: the same on a 64-gon (an ellipse outline);
//! - `paper/predict`, `paper/online_step`: the paper's model;
//! - `online_step_gauss_newton`: one Gauss–Newton step with the posterior (contact, box), and
//!   `online_step_gd_posterior`: the paper's step with the posterior kept beside it, as `pushlab eval`
//!   and the app run it;
//! - `online_frame/combined` and `online_frame/weighted`: one frame of a run along a push (the
//!   paper's gradient descent with the posterior, the fixed run scored up front), alone and with
//!   the physics-only model learning beside it and the two weighed (`learn::ModelWeight`): what
//!   the weighting costs a frame;
//! - `landscape_64`: the loss over a 64 × 64 grid of COM offsets on the last 25 frames (contact, box);
//! - `best_fit/best_fit_100`: the best θ for a whole push of 100 samples (contact, box);
//! - `train/train_epoch` (the paper's model) and `train/train_epoch_contact`: one epoch's training,
//!   with the training's one-off work; `train/train_5_epochs_contact` gives an epoch's cost beyond it.

// The platform's sin, cos and hypot are fine for synthetic inputs here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]

use std::hint::black_box;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, OnceLock};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Point2;
use pushlab_core::experiment::best_fit;
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::inspect::{ComGrid, com_landscape};
use pushlab_core::learn::{
    ContactTrajectory, ModelWeight, OnlineConfig, OnlineRun, OnlineState, Optimizer, TrainConfig,
    WeightConfig, learn_step_in_place, train_contact, train_paper,
};
use pushlab_core::model::{
    CombinedModel, ContactGeometry, ObjectMotion, OnlineModel, OnlineParams, PhysicsOnlyModel,
    Sample, SampleInput, SharedOnlineModel, lynch,
};
use pushlab_core::rng::SplitMix64;
use pushlab_core::trajectory::{Frame, Trajectory};

/// Front-face pushes on a 0.3 × 0.4 m box by a 0.05 m disc, moved by Lynch's model: realistic input
/// ranges, so that the network's ReLUs are as active as on real data.
fn synthetic_trajectories(count: usize, length: usize, seed: u64) -> Vec<Vec<Sample>> {
    let mut rng = SplitMix64::new(seed);
    let (half_width, half_length, radius, h) = (0.15, 0.2, 0.05, 0.1);
    (0..count)
        .map(|_| {
            let y = (rng.uniform() - 0.5) * 2.0 * half_length * 0.8;
            let angle = (rng.uniform() - 0.5) * 0.6;
            (0..length)
                .map(|frame| {
                    let u = [0.01 * angle.cos(), 0.01 * angle.sin()];
                    let m = lynch([-half_width, y], u, h);
                    Sample {
                        input: SampleInput {
                            robot_in_object: [-half_width - radius, y + 0.001 * rng.normal()],
                            robot_motion_in_object: u,
                        },
                        target: ObjectMotion {
                            translation: m.translation,
                            rotation: m.rotation,
                        },
                        frame,
                    }
                })
                .collect()
        })
        .collect()
}

fn box_geometry() -> Arc<ContactGeometry> {
    Arc::new(ContactGeometry::new(
        &Outline::rectangle(0.3, 0.4).expect("valid box"),
        0.05,
    ))
}

/// The samples of `synthetic_trajectories` moved onto a 64-gon approximating an ellipse of the box's
/// size: the pusher is put just outside the outline at the same height.
fn on_64gon(data: &[Vec<Sample>]) -> (Arc<ContactGeometry>, Vec<Sample>) {
    let outline = Outline::ellipse(Point2::origin(), 0.15, 0.2, 64).expect("valid 64-gon");
    let geometry = Arc::new(ContactGeometry::new(&outline, 0.05));
    let samples = data
        .iter()
        .flatten()
        .map(|s| {
            let y = s.input.robot_in_object[1].clamp(-0.19, 0.19);
            let x = -0.15 * (1.0 - (y / 0.2).powi(2)).sqrt() - 0.05;
            Sample {
                input: SampleInput {
                    robot_in_object: [x, y],
                    ..s.input
                },
                ..*s
            }
        })
        .collect();
    (geometry, samples)
}

fn config() -> TrainConfig {
    TrainConfig {
        epochs: 5,
        theta0: Some(OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.1,
        }),
        ..TrainConfig::default()
    }
}

/// Learners of trained models and the samples they run on: the contact model on a box and on a
/// 64-gon, and the paper model. Trained on first use: a run filtered to another benchmark does not
/// train them.
struct Trained {
    contact_box: Learner,
    contact_64gon: Learner,
    paper: Learner,
    samples: Vec<Sample>,
    samples_64gon: Vec<Sample>,
}

static TRAINED: OnceLock<Trained> = OnceLock::new();

/// A learner shared between benchmarks.
type Learner = Arc<dyn OnlineModel + Send + Sync>;
/// Which learner and samples a benchmark runs.
type Pick = fn(&Trained) -> (&Learner, &[Sample]);

fn trained() -> &'static Trained {
    TRAINED.get_or_init(|| {
        let data = synthetic_trajectories(20, 100, 1);
        let no = AtomicBool::new(false);
        let geometry = box_geometry();
        let trajectories: Vec<ContactTrajectory> = data
            .iter()
            .map(|samples| ContactTrajectory {
                geometry: &geometry,
                samples,
            })
            .collect();
        let contact = CombinedModel::Contact(Arc::new(
            train_contact(&trajectories, &config(), &mut |_| {}, &no)
                .expect("synthetic data trains")
                .model,
        ));
        let paper = CombinedModel::Paper(Arc::new(
            train_paper(&data, &config(), &mut |_| {}, &no)
                .expect("synthetic data trains")
                .model,
        ));
        let (gon, samples_64gon) = on_64gon(&data);
        Trained {
            contact_box: contact.on_object(Some(&geometry)).expect("outline"),
            contact_64gon: contact.on_object(Some(&gon)).expect("outline"),
            paper: paper.on_object(None).expect("no outline needed"),
            samples: data.into_iter().flatten().collect(),
            samples_64gon,
        }
    })
}

fn bench_predict(c: &mut Criterion, name: &str, pick: Pick) {
    let mut i = 0;
    c.bench_function(name, |b| {
        let (model, samples) = pick(trained());
        let theta = model.theta0();
        b.iter(|| {
            i = (i + 1) % samples.len();
            black_box(model.predict(black_box(&samples[i].input), black_box(&theta)))
        })
    });
}

fn bench_online_step(c: &mut Criterion, name: &str, pick: Pick) {
    let descent = OnlineConfig::default().descent();
    let mut i = 0;
    // θ carries over from one batch of iterations to the next, as along a real trajectory.
    let mut carried = None;
    c.bench_function(name, |b| {
        let (model, samples) = pick(trained());
        let theta = carried.get_or_insert_with(|| model.theta0());
        b.iter(|| {
            i = (i + 1) % samples.len();
            let step = model.online_step(black_box(&samples[i]), theta, &descent);
            *theta = step.theta_after;
            black_box(step)
        })
    });
}

fn predict(c: &mut Criterion) {
    bench_predict(c, "predict", |t| (&t.contact_box, &t.samples));
    bench_predict(c, "predict_64gon", |t| (&t.contact_64gon, &t.samples_64gon));
    bench_predict(c, "paper/predict", |t| (&t.paper, &t.samples));
}

fn online_step(c: &mut Criterion) {
    bench_online_step(c, "online_step", |t| (&t.contact_box, &t.samples));
    bench_online_step(c, "online_step_64gon", |t| {
        (&t.contact_64gon, &t.samples_64gon)
    });
    bench_online_step(c, "paper/online_step", |t| (&t.paper, &t.samples));
}

fn bench_learn_step(c: &mut Criterion, name: &str, optimizer: Optimizer) {
    let config = OnlineConfig {
        optimizer,
        ..OnlineConfig::default()
    };
    let mut i = 0;
    let mut carried = None;
    c.bench_function(name, |b| {
        let t = trained();
        let model = t.contact_box.as_ref();
        let state = carried.get_or_insert_with(|| OnlineState::start(model, config.optimizer));
        b.iter(|| {
            i = (i + 1) % t.samples.len();
            black_box(learn_step_in_place(
                model,
                black_box(&t.samples[i]),
                state,
                &config,
            ))
        })
    });
}

fn online_step_posterior(c: &mut Criterion) {
    bench_learn_step(c, "online_step_gauss_newton", Optimizer::GaussNewton);
    bench_learn_step(c, "online_step_gd_posterior", Optimizer::Gd);
}

fn landscape(c: &mut Criterion) {
    let t = trained();
    let frames = &t.samples[..25];
    let model = t.contact_box.as_ref();
    let grid = ComGrid {
        centre: [0.0, 0.0],
        half_width: 0.2,
        cells: 64,
    };
    let h = model.theta0().h;
    let mut group = c.benchmark_group("landscape");
    group.sample_size(20);
    group.bench_function("landscape_64", |b| {
        b.iter(|| black_box(com_landscape(model, frames, &grid, h, &|| false)))
    });
    group.finish();
}

/// The best θ for a whole push (`pushlab eval --best-fit`, the app's Steer tab): one trajectory of
/// 100 samples (contact, box).
fn best_fit_100(c: &mut Criterion) {
    let t = trained();
    let push = &t.samples[..100];
    let model = t.contact_box.as_ref();
    let mut group = c.benchmark_group("best_fit");
    group.sample_size(10);
    group.bench_function("best_fit_100", |b| {
        b.iter(|| black_box(best_fit(model, push, &|| false)))
    });
    group.finish();
}

fn train_epoch(c: &mut Criterion) {
    let data = synthetic_trajectories(250, 100, 2);
    let samples: usize = data.iter().map(Vec::len).sum();
    let config = TrainConfig {
        epochs: 1,
        validation_fraction: 0.0,
        ..config()
    };
    let cancel = AtomicBool::new(false);
    let geometry = box_geometry();
    let trajectories: Vec<ContactTrajectory> = data
        .iter()
        .map(|samples| ContactTrajectory {
            geometry: &geometry,
            samples,
        })
        .collect();
    let mut group = c.benchmark_group("train");
    group.throughput(Throughput::Elements(samples as u64));
    group.sample_size(20);
    group.bench_function("train_epoch", |b| {
        b.iter(|| black_box(train_paper(&data, &config, &mut |_| {}, &cancel)))
    });
    group.bench_function("train_epoch_contact", |b| {
        b.iter(|| black_box(train_contact(&trajectories, &config, &mut |_| {}, &cancel)))
    });
    // One training of five epochs: against `train_epoch_contact` (one), what an epoch costs once the
    // training's one-off work (normalisation, μ, the θ scales' curvature) is done. Its throughput
    // counts the samples of all five epochs.
    let five = TrainConfig {
        epochs: 5,
        ..config
    };
    group.throughput(Throughput::Elements(5 * samples as u64));
    group.bench_function("train_5_epochs_contact", |b| {
        b.iter(|| black_box(train_contact(&trajectories, &five, &mut |_| {}, &cancel)))
    });
    group.finish();
}

/// A 1,000-frame push at 100 Hz on the 0.3 × 0.4 m box, pushed along +x at its front face while
/// turning slowly, the disc 2 cm off centre.
fn box_push() -> Arc<Trajectory> {
    let frames = (0..1000)
        .map(|i| {
            let t = i as f64 * 0.01;
            let object = Pose2::new(0.05 * t, 0.0, 0.1 * t);
            let robot = object.point_in_world(Point2::new(-0.2, 0.02));
            Frame {
                time: t,
                robot,
                object,
            }
        })
        .collect();
    Arc::new(Trajectory::new(frames))
}

fn online_frame(c: &mut Criterion) {
    let learner = &trained().contact_box;
    let trajectory = box_push();
    let outline = Outline::rectangle(0.3, 0.4).expect("valid box");
    let physics = PhysicsOnlyModel::new(outline, 0.05, 0.01, learner.loss_scale());
    let run = |model: SharedOnlineModel| {
        OnlineRun::new(model, Arc::clone(&trajectory), 1, OnlineConfig::default())
    };
    let mut group = c.benchmark_group("online_frame");
    group.throughput(Throughput::Elements(trajectory.len() as u64));
    group.bench_function("combined", |b| {
        b.iter(|| {
            let mut run = run(Arc::clone(learner));
            run.learn_all(&[]);
            black_box(run.frontier())
        });
    });
    group.bench_function("weighted", |b| {
        b.iter(|| {
            let beside = run(Arc::new(physics.clone()));
            let weight = ModelWeight::new(WeightConfig::default());
            let mut run = run(Arc::clone(learner)).with_physics_beside(beside, weight);
            run.learn_all(&[]);
            black_box(run.frontier())
        });
    });
    group.finish();
}

criterion_group!(
    benches,
    predict,
    online_step,
    online_step_posterior,
    online_frame,
    landscape,
    best_fit_100,
    train_epoch
);
criterion_main!(benches);
