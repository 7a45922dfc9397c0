//! A rendered snapshot of the main window (committed under tests/snapshots/). Rendering uses wgpu on
//! the CPU (Mesa lavapipe or llvmpipe); `scripts/test` installs the driver when missing.

use egui_kittest::Harness;
use pushlab::app::state::Persisted;
use pushlab::app::{PushlabApp, initial_state};

#[test]
fn main_window_after_learning_forty_frames() {
    let app = PushlabApp::new(initial_state(&[], Persisted::default()));
    let mut harness = Harness::builder()
        .with_size([1400.0, 900.0])
        .with_render_cursor(false)
        .build_ui_state(|ui, app: &mut PushlabApp| app.show(ui), app);
    harness.run_steps(2);
    for _ in 0..4 {
        harness
            .state_mut()
            .state
            .apply(pushlab::app::state::Command::Timeline(
                pushlab::app::state::playback::timeline::TimelineCommand::Step(10),
            ));
    }
    harness.run_steps(3);
    harness.snapshot("main_window");
}
