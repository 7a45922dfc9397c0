//! The frames of a rendered push: the app's state played frame by frame — learning online as the
//! window does when it plays, by the same run — and each frame's scene laid out by the app's own
//! scene painter (`panels::scene::picture`) under a caption line, with the app's loss and θ plots
//! below it when asked (`panels::plots`, as the demo layout shows them), tessellated by egui and
//! painted into pixels ([`super::raster`]).

use eframe::egui;

use super::raster::{Canvas, Textures};
use crate::app::colors;
use crate::app::panels::plots;
use crate::app::panels::scene::{self, SceneView};
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};

/// A push being rendered: the state, the scene's view and egui's textures.
pub struct SceneFrames {
    ctx: egui::Context,
    state: AppState,
    view: SceneView,
    textures: Textures,
    size: [usize; 2],
    with_plots: bool,
}

impl SceneFrames {
    /// Renders the recording `state` shows, at `size` pixels (one pixel a point), with the plots
    /// below the scene or not.
    pub fn new(state: AppState, size: [usize; 2], with_plots: bool, theme: egui::Theme) -> Self {
        let ctx = egui::Context::default();
        ctx.set_theme(theme);
        Self {
            ctx,
            state,
            view: SceneView::default(),
            textures: Textures::default(),
            size,
            with_plots,
        }
    }

    pub fn state(&self) -> &AppState {
        &self.state
    }

    /// Where a point of the table (metres) was drawn in the last frame, pixels from the top left.
    pub fn pixel_of(&self, world: nalgebra::Point2<f64>) -> [f32; 2] {
        let at = self.view.projection().to_screen(world);
        [at.x, at.y]
    }

    /// Moves to recording frame `k` as the window's timeline does, its run learning the frames
    /// passed. A jump longer than the app learns on the UI thread is learned on its worker
    /// (`learning_ahead`); the frame waits for it, so that θ is the one learned up to `k`.
    pub fn show(&mut self, k: usize) {
        if k != self.state.frame() {
            self.state
                .apply(Command::Timeline(TimelineCommand::SeekTo(k)));
        }
        while self.state.learning_ahead().is_some() {
            self.state.advance(0.0);
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }

    /// The frame shown, as RGBA bytes row by row.
    pub fn draw(&mut self) -> Vec<u8> {
        let [width, height] = self.size;
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(width as f32, height as f32),
            )),
            ..egui::RawInput::default()
        };
        let (state, view, with_plots) = (&self.state, &mut self.view, self.with_plots);
        let mut output = self.ctx.run_ui(input, |ui| {
            egui::Panel::top("caption").show(ui, |ui| {
                ui.add_space(2.0);
                // One line at any width: the text scales with the frame (13 points at 720p).
                let size = (width as f32 / 95.0).clamp(8.0, 20.0);
                ui.add(
                    egui::Label::new(egui::RichText::new(caption(state)).monospace().size(size))
                        .wrap_mode(egui::TextWrapMode::Truncate),
                );
                ui.add_space(2.0);
            });
            if with_plots {
                // The plots' clicks would seek: a picture has none, and what they ask is dropped.
                egui::Panel::bottom("plots")
                    .exact_size(0.42 * height as f32)
                    .show(ui, |ui| plots::ui(ui, state, &mut Vec::new()));
            }
            egui::CentralPanel::default()
                .frame(egui::Frame::NONE)
                .show(ui, |ui| scene::picture(ui, state, view));
        });
        self.textures.update(&output.textures_delta);
        output.textures_delta.clear();
        let primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        let background = colors::of(&self.ctx).background;
        let mut canvas = Canvas::new(width, height, background);
        canvas.paint(&primitives, &self.textures, output.pixels_per_point);
        canvas.rgba()
    }
}

/// The caption line: the recording, the frame and its time, θ.
fn caption(state: &AppState) -> String {
    let Some(recording) = state.recording() else {
        return String::new();
    };
    let frame = state.frame();
    let time = (recording.trajectory.frames.get(frame)).map_or(0.0, |f| f.time);
    let theta = state.theta().map_or(String::new(), |t| {
        format!(
            "  θ: COM ({:+.1}, {:+.1}) mm, h {:.1} mm",
            t.com_offset[0] * 1e3,
            t.com_offset[1] * 1e3,
            t.h * 1e3
        )
    });
    format!(
        "{}  frame {frame}/{}  {time:.2} s{theta}",
        recording.name,
        recording.trajectory.len().saturating_sub(1)
    )
}
