//! The `pushlab` package's integration tests, as one test binary.
//!
//! Each file below is one concern's tests (`app_*` drive the app headlessly with egui_kittest,
//! `cli_*` run the built `pushlab` binary). They are modules of one binary, not a binary each:
//! every test binary links the whole app (egui, wgpu, the core), and on two cores linking and
//! running ~40 binaries one after the other took a large share of CI's time. One binary also runs
//! the tests of every file side by side. Run one file's tests with `cargo test --test integration
//! app_ui::` (a name filter), as before with `--test app_ui`.

// What the files share.
mod cli_common;
mod common;
mod live_robot;
mod sandbox_robot;
mod skip;

mod app_bags;
mod app_browser;
mod app_camera;
mod app_controller_here;
mod app_datasets;
mod app_demo;
mod app_equals_eval;
mod app_export_plots;
mod app_export_video;
mod app_files;
mod app_footprint;
mod app_labels;
mod app_landscape;
mod app_live;
mod app_live_drive;
mod app_next_push;
mod app_proposals;
mod app_sandbox;
mod app_sandbox_goal;
mod app_scene;
mod app_snapshot;
mod app_ui;
mod app_uncertainty;
mod app_workflows;
mod architecture;
mod cli_control_robot;
mod cli_import;
mod cli_import_cameras;
mod cli_label_proposals;
mod cli_live;
mod cli_model_files;
mod cli_push_t;
mod cli_push_t_datasets;
mod cli_render;
mod cli_simulate;
mod cli_suggest;
mod cli_suite;
mod cli_train_eval;
mod cli_validate;
mod docs_links;
