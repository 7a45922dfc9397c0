//! Speed of the model: one prediction, one online step (predict + 5 gradient steps) and one epoch of
//! offline training. Run with `cargo bench -p pushlab-core --bench model`.

use std::hint::black_box;
use std::sync::OnceLock;
use std::sync::atomic::AtomicBool;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pushlab_core::learn::{OnlineConfig, OnlineModel, TrainConfig, train_combined};
use pushlab_core::model::{CombinedModel, ObjectMotion, OnlineParams, Sample, SampleInput, lynch};
use pushlab_core::rng::SplitMix64;

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

fn trained_model() -> (CombinedModel, Vec<Sample>) {
    let data = synthetic_trajectories(20, 100, 1);
    let config = TrainConfig {
        epochs: 5,
        theta0: Some(OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.1,
        }),
        ..TrainConfig::default()
    };
    let trained = train_combined(&data, &config, &mut |_| {}, &AtomicBool::new(false))
        .expect("synthetic data trains");
    (trained.model, data.into_iter().flatten().collect())
}

/// The trained model, trained on first use: a run filtered to another benchmark does not train it.
static TRAINED: OnceLock<(CombinedModel, Vec<Sample>)> = OnceLock::new();

fn predict(c: &mut Criterion) {
    let mut i = 0;
    c.bench_function("predict", |b| {
        let (model, samples) = TRAINED.get_or_init(trained_model);
        let theta = model.theta0();
        b.iter(|| {
            i = (i + 1) % samples.len();
            black_box(model.predict(black_box(&samples[i].input), black_box(&theta)))
        })
    });
}

fn online_step(c: &mut Criterion) {
    let config = OnlineConfig::default();
    let mut i = 0;
    // θ carries over from one batch of iterations to the next, as along a real trajectory.
    let mut carried = None;
    c.bench_function("online_step", |b| {
        let (model, samples) = TRAINED.get_or_init(trained_model);
        let theta = carried.get_or_insert_with(|| model.theta0());
        b.iter(|| {
            i = (i + 1) % samples.len();
            let step = model.online_step(black_box(&samples[i]), theta, &config);
            *theta = step.theta_after;
            black_box(step)
        })
    });
}

fn train_epoch(c: &mut Criterion) {
    let data = synthetic_trajectories(250, 100, 2);
    let samples: usize = data.iter().map(Vec::len).sum();
    let config = TrainConfig {
        epochs: 1,
        validation_fraction: 0.0,
        theta0: Some(OnlineParams {
            com_offset: [0.0, 0.0],
            h: 0.1,
        }),
        ..TrainConfig::default()
    };
    let cancel = AtomicBool::new(false);
    let mut group = c.benchmark_group("train");
    group.throughput(Throughput::Elements(samples as u64));
    group.sample_size(20);
    group.bench_function("train_epoch", |b| {
        b.iter(|| black_box(train_combined(&data, &config, &mut |_| {}, &cancel)))
    });
    group.finish();
}

criterion_group!(benches, predict, online_step, train_epoch);
criterion_main!(benches);
