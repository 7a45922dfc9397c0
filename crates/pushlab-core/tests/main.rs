//! pushlab-core's integration tests, as one test binary: each file below is one concern's tests,
//! a module of this binary rather than a binary of its own, so that they are linked once and run
//! side by side (see the `pushlab` package's `tests/main.rs`). Run one file's tests with
//! `cargo test -p pushlab-core --test core recordings_mit::`.

// The platform's sin, cos and hypot are fine for expected values here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]

// What the files share.
mod allocations;
mod pusht_common;
#[path = "../../../tests/sandbox_robot/mod.rs"]
mod sandbox_robot;
#[path = "../../../tests/skip.rs"]
mod skip;
mod toy;

/// Notes each thread's allocations: how many, and the largest (`allocations`).
#[global_allocator]
static ALLOCATOR: allocations::Noting = allocations::Noting;

mod bag_choice;
mod camera_video;
mod carry_theta;
mod com_misfit;
mod control_allocations;
mod correlated_errors;
mod datasets_fuzz_seeds;
mod drive_foxglove;
mod experiment_load_all;
mod labels_sample_data;
mod learning;
mod live_foxglove;
mod live_learning;
mod live_session;
mod live_tf_chain;
mod load_in_slices;
mod model_files;
mod online_wild_rates;
mod pusher_speed;
mod recordings_bags;
mod recordings_cameras;
mod recordings_lerobot;
mod recordings_lerobot_images;
mod recordings_mit;
mod recordings_nasty;
mod recordings_native;
mod recordings_pusht;
mod sandbox;
mod sim_non_convex;
mod sim_physics;
mod sim_push_plans;
mod sim_sets;
mod suggest;
mod uncertainty;
