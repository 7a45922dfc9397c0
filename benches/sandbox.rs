//! Push it yourself, measured (issue #65; docs/src/teaching.md and performance.md quote it).
//!
//! 1. **The sandbox's own CPU per step**: one call of the app state's `advance(0.1)` that makes
//!    one frame — the simulator's step, the frame grown on the live path, its sample learned, the
//!    prediction ahead — timed on the UI thread as the app makes it (no drawing), over every frame
//!    of the pushes below; and apart, the step that ends a push (its review against the ranking's
//!    choice runs then).
//! 2. **The lesson**: on `--seeds` mysteries of the box (seeds 0…N−1), a first push straight into
//!    the front face (the same for both), then three more either the ranking's best (Suggest the
//!    next push, from where learning stands) or random (a face, an offset within ±0.6 of its half
//!    length, an angle within ±20°, 10 cm: the grid's range, seeded), and the model's COM error
//!    after each, by median over the seeds.
//!
//! Run with `cargo bench -p pushlab --bench sandbox -- [--seeds N] [--optimizer gd|gauss-newton]`
//! (the learner: the paper's gradient descent, the app's default, or Gauss–Newton).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::{Duration, Instant};

use pushlab::app::hook::{self, HookCommand, HookPush};
use pushlab::app::initial_state;
use pushlab::app::state::{AppState, Persisted};
use pushlab_core::learn::Optimizer;
use pushlab_core::rng::SplitMix64;

fn send(state: &mut AppState, command: &HookCommand) {
    for c in hook::translate(command, state).unwrap().commands {
        state.apply(c);
    }
}

/// The frames of the push being made, each timed; the push-ending step apart.
#[derive(Default)]
struct Steps {
    frame_us: Vec<f64>,
    ending_us: Vec<f64>,
}

/// Lets a tenth of a second pass at a time until the push ends (timing each step that made a
/// frame), then until the work off the UI thread (a ranking) ends.
fn finish(state: &mut AppState, steps: &mut Steps) {
    loop {
        let before = state.recording().map_or(0, |r| r.trajectory.len());
        let started = Instant::now();
        state.advance(0.1);
        let took = started.elapsed().as_secs_f64() * 1e6;
        let pushing = state.sandbox().unwrap().sandbox().is_pushing();
        if !pushing {
            steps.ending_us.push(took);
            break;
        }
        if state.recording().map_or(0, |r| r.trajectory.len()) > before {
            steps.frame_us.push(took);
        }
    }
    while state.is_busy() {
        state.advance(0.0);
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn com_error(state: &AppState) -> f64 {
    let theta = state.theta().unwrap();
    let truth = state
        .sandbox()
        .unwrap()
        .sandbox()
        .mystery()
        .hidden
        .com_offset;
    (theta.com_offset[0] - truth[0]).hypot(theta.com_offset[1] - truth[1])
}

/// The lesson on one seed: the COM error after each of the four pushes.
fn lesson(seed: u64, ranked: bool, optimizer: Optimizer, steps: &mut Steps) -> [f64; 4] {
    let mut settings = Persisted::default();
    settings.online.optimizer = optimizer;
    let mut state = initial_state(&[], settings);
    send(
        &mut state,
        &hook::parse(&format!(
            r#"{{"sandbox": {{"seed": {seed}, "object": "box"}}}}"#
        ))
        .unwrap(),
    );
    let push = |push: HookPush| HookCommand {
        push: Some(push),
        ..HookCommand::default()
    };
    send(
        &mut state,
        &push(HookPush {
            face: "front".into(),
            offset: 0.0,
            angle: 0.0,
            length: 0.1,
        }),
    );
    finish(&mut state, steps);
    let mut errors = [com_error(&state), 0.0, 0.0, 0.0];
    let mut random = SplitMix64::new(seed ^ 0x5EED);
    for error in &mut errors[1..] {
        let next = if ranked {
            send(
                &mut state,
                &HookCommand {
                    suggest: Some(true),
                    ..HookCommand::default()
                },
            );
            finish_ranking(&mut state);
            let shown = hook::shown(&state).sandbox.unwrap();
            shown.suggested.first().expect("a suggestion").push.clone()
        } else {
            let face = ["front", "left", "back", "right"][(random.uniform() * 4.0) as usize];
            // The box is 0.3 × 0.4 m: the faces' half lengths.
            let half = if face == "front" || face == "back" {
                0.2
            } else {
                0.15
            };
            HookPush {
                face: face.into(),
                offset: (2.0 * random.uniform() - 1.0) * 0.6 * half,
                angle: (2.0 * random.uniform() - 1.0) * 20.0,
                length: 0.1,
            }
        };
        send(&mut state, &push(next));
        finish(&mut state, steps);
        *error = com_error(&state);
    }
    errors
}

fn finish_ranking(state: &mut AppState) {
    while state.is_busy() {
        state.advance(0.0);
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

fn quantile(mut values: Vec<f64>, q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    values[((values.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    let mut seeds = 50u64;
    let mut optimizer = Optimizer::default();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--seeds" {
            seeds = args.next().and_then(|s| s.parse().ok()).expect("--seeds N");
        } else if arg == "--optimizer" {
            optimizer = (args.next().as_deref())
                .and_then(Optimizer::from_name)
                .expect("--optimizer gd|gauss-newton");
        }
    }
    let mut steps = Steps::default();
    let mut by_strategy = Vec::new();
    for ranked in [true, false] {
        let runs: Vec<[f64; 4]> = (0..seeds)
            .map(|s| lesson(s, ranked, optimizer, &mut steps))
            .collect();
        by_strategy.push((ranked, runs));
    }
    let us = |v: &[f64]| {
        format!(
            "median {:.0} µs, p99 {:.0} µs, worst {:.0} µs",
            median(v.to_vec()),
            quantile(v.to_vec(), 0.99),
            quantile(v.to_vec(), 1.0)
        )
    };
    println!(
        "sandbox step (simulate, grow, learn one frame; no drawing): {} over {} frames",
        us(&steps.frame_us),
        steps.frame_us.len()
    );
    println!(
        "push-ending step (with its review against the ranking): {} over {} pushes",
        us(&steps.ending_us),
        steps.ending_us.len()
    );
    println!(
        "median COM error over {seeds} box mysteries, mm, learner {} (first push straight into \
         the front face):",
        optimizer.name()
    );
    println!("  pushes            1      2      3      4");
    for (ranked, runs) in &by_strategy {
        let column = |k: usize| median(runs.iter().map(|r| r[k] * 1e3).collect());
        println!(
            "  {:<14} {:>6.1} {:>6.1} {:>6.1} {:>6.1}",
            if *ranked { "ranked" } else { "random" },
            column(0),
            column(1),
            column(2),
            column(3)
        );
    }
}
