//! Which path draws `pushlab render`'s frames faster: the CPU rasterizer it uses (`app::render`:
//! the app's scene laid out and tessellated by egui, the triangles painted on the CPU) or egui's
//! wgpu renderer, as the snapshot tests render (`egui_kittest`, on this machine Mesa's lavapipe,
//! a CPU Vulkan driver: there is no GPU). Both draw the same scene of a sample push at 1280 × 720,
//! learning a frame between two draws; the time of the draw alone is counted.
//!
//! Run: `cargo bench -p pushlab --bench render_frame` (`WGPU_BACKEND=vulkan` for the wgpu path).
//! Under `cargo test` it draws two frames each way and checks only that pixels came out (timing
//! is measured here, never asserted in a test).

use std::path::Path;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use pushlab::app::initial_state;
use pushlab::app::panels::scene::{self, SceneView};
use pushlab::app::render::SceneFrames;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{AppState, Command, Persisted};

const SIZE: [usize; 2] = [1280, 720];

fn state() -> AppState {
    let push = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data/box1-paper-lr-front/online_000.csv");
    initial_state(&[push], Persisted::default())
}

fn median(mut times: Vec<Duration>) -> Duration {
    times.sort();
    times[times.len() / 2]
}

fn main() {
    let measuring = std::env::args().any(|a| a == "--bench");
    let frames = if measuring { 60 } else { 2 };

    let mut cpu = SceneFrames::new(state(), SIZE, false, eframe::egui::Theme::Dark);
    let mut times = Vec::new();
    for k in 0..frames {
        cpu.show(k);
        let started = Instant::now();
        let rgba = cpu.draw();
        times.push(started.elapsed());
        assert_eq!(rgba.len(), SIZE[0] * SIZE[1] * 4);
    }
    println!(
        "CPU rasterizer: {:.1} ms a frame (median of {frames})",
        median(times).as_secs_f64() * 1e3
    );

    let mut harness = Harness::builder()
        .with_size([SIZE[0] as f32, SIZE[1] as f32])
        .build_ui_state(
            |ui, (state, view): &mut (AppState, SceneView)| scene::picture(ui, state, view),
            (state(), SceneView::default()),
        );
    let mut times = Vec::new();
    for _ in 0..frames {
        harness
            .state_mut()
            .0
            .apply(Command::Timeline(TimelineCommand::Step(1)));
        let started = Instant::now();
        harness.run_steps(1);
        match harness.render() {
            Ok(image) => assert_eq!(image.width() as usize, SIZE[0]),
            Err(why) => {
                println!("wgpu renderer: not measured ({why})");
                return;
            }
        }
        times.push(started.elapsed());
    }
    println!(
        "wgpu renderer (egui_kittest): {:.1} ms a frame (median of {frames})",
        median(times).as_secs_f64() * 1e3
    );
}
