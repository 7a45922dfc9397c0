//! The camera panel: what each shown camera saw at the frame the scene shows, one view per stream
//! stacked top to bottom, each with its frame number, its offset from the scene frame's time, and
//! its own zoom (wheel about the pointer) and pan (drag); a double-click fits the image again.
//!
//! Reads [`Cameras::shown`]; the only state it keeps is its own: each stream's zoom and the texture
//! of the frame it last uploaded, kept on screen until the next frame has been decoded, so that
//! scrubbing never flashes an empty panel.
//!
//! [`Cameras::shown`]: crate::app::state::playback::cameras::Cameras::shown

use std::collections::HashMap;

use eframe::egui::{self, Color32, Pos2, Rect, Vec2};
use pushlab_core::recording::camera::RgbaImage;

use crate::app::state::AppState;
use crate::app::state::playback::cameras::CameraFrame;
use crate::app::state::sources::live::LiveImage;

/// A frame's error, above its image.
const ERROR_COLOR: Color32 = Color32::from_rgb(255, 110, 90);

/// Most a view zooms in.
const MAX_ZOOM: f32 = 16.0;

/// The camera panel's own state, per stream name.
#[derive(Default)]
pub struct CameraView {
    streams: HashMap<String, StreamView>,
}

#[derive(Default)]
struct StreamView {
    zoom: ImageZoom,
    /// The frame uploaded last and its texture.
    texture: Option<(usize, egui::TextureHandle)>,
}

/// Which part of an image a view shows: `zoom` ≥ 1 times the fitted image, around `center` in
/// texture coordinates (0..1 on each side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageZoom {
    zoom: f32,
    center: Vec2,
}

impl Default for ImageZoom {
    fn default() -> Self {
        Self {
            zoom: 1.0,
            center: Vec2::splat(0.5),
        }
    }
}

impl ImageZoom {
    /// The zoom factor (1: the whole image).
    pub fn zoom(&self) -> f32 {
        self.zoom
    }

    /// The texture coordinates shown.
    pub fn uv(&self) -> Rect {
        Rect::from_center_size(self.center.to_pos2(), Vec2::splat(1.0 / self.zoom))
    }

    /// Zooms by `factor` keeping the image point under `pointer` where it is; `rect` is where the
    /// image is drawn.
    pub fn zoom_about(&mut self, factor: f32, pointer: Pos2, rect: Rect) {
        let along = ((pointer - rect.min) / rect.size()).clamp(Vec2::ZERO, Vec2::splat(1.0));
        let uv = self.uv();
        let under = uv.min + along * uv.size();
        self.zoom = (self.zoom * factor).clamp(1.0, MAX_ZOOM);
        let min = under - along / self.zoom;
        self.center = min.to_vec2() + Vec2::splat(0.5 / self.zoom);
        self.clamp();
    }

    /// Moves the image by `delta` points on the screen; `rect` is where it is drawn.
    pub fn pan(&mut self, delta: Vec2, rect: Rect) {
        self.center -= delta / rect.size() / self.zoom;
        self.clamp();
    }

    /// Keeps the view inside the image.
    fn clamp(&mut self) {
        let half = 0.5 / self.zoom;
        self.center = self
            .center
            .clamp(Vec2::splat(half), Vec2::splat(1.0 - half));
    }
}

/// The camera panel on the right of the scene's area, resizable, whenever the recording shown has a
/// camera shown (in the usual layout and the presentation's); call before drawing the scene.
pub fn beside_scene(ui: &mut egui::Ui, state: &AppState, view: &mut CameraView) {
    if !state.cameras().any_shown() && state.live_images().is_none() {
        return;
    }
    let width = ui.available_width();
    egui::Panel::right("cameras")
        .default_size(width * 0.5)
        .min_size(160.0)
        .max_size((width - 200.0).max(160.0))
        .resizable(true)
        .show(ui, |ui| self::ui(ui, state, view));
}

/// Draws each shown stream, sharing the height among them.
pub fn ui(ui: &mut egui::Ui, state: &AppState, view: &mut CameraView) {
    if let Some((images, dropped)) = state.live_images() {
        live_ui(ui, state, images, dropped, view);
        return;
    }
    let frames = state.cameras().shown(state.timeline().frame_time());
    if frames.is_empty() {
        return;
    }
    let height = ui.available_height() / frames.len() as f32;
    for frame in &frames {
        let stream = view.streams.entry(frame.stream.name.clone()).or_default();
        ui.allocate_ui(egui::vec2(ui.available_width(), height), |ui| {
            stream_ui(ui, frame, stream);
        });
    }
}

/// One stream: its caption, then its image (or why there is none).
fn stream_ui(ui: &mut egui::Ui, frame: &CameraFrame<'_>, view: &mut StreamView) {
    // The caption moves below the name as a whole when the panel is narrow: broken inside, it left
    // "ms" alone on a line.
    ui.horizontal_wrapped(|ui| {
        ui.strong(&frame.stream.name);
        ui.add(egui::Label::new(caption(frame)).wrap_mode(egui::TextWrapMode::Extend));
    });
    if let Some(Ok(image)) = &frame.decoded
        && let Some(index) = frame.frame
    {
        upload(ui, view, index, &frame.stream.name, image);
    }
    if let Some(Err(problem)) = &frame.decoded {
        ui.colored_label(ERROR_COLOR, format!("frame cannot be shown: {problem}"));
    }
    // Before the first frame, or at a frame that cannot be shown, no older image stands in for it.
    if frame.frame.is_none() || matches!(frame.decoded, Some(Err(_))) {
        view.texture = None;
    }
    draw_texture(ui, view);
}

/// Uploads picture `number` of a stream as its texture, unless it is the one shown already.
fn upload(ui: &egui::Ui, view: &mut StreamView, number: usize, name: &str, image: &RgbaImage) {
    if view
        .texture
        .as_ref()
        .is_some_and(|(shown, _)| *shown == number)
    {
        return;
    }
    let pixels = color_image(image);
    match &mut view.texture {
        Some((shown, texture)) => {
            texture.set(pixels, egui::TextureOptions::LINEAR);
            *shown = number;
        }
        None => {
            let name = format!("camera {name}");
            let texture = ui
                .ctx()
                .load_texture(name, pixels, egui::TextureOptions::LINEAR);
            view.texture = Some((number, texture));
        }
    }
}

/// The rest of the view: its texture fitted, zoomed and panned, on a dark ground.
fn draw_texture(ui: &mut egui::Ui, view: &mut StreamView) {
    let area = ui.available_rect_before_wrap();
    let response = ui.allocate_rect(area, egui::Sense::click_and_drag());
    let painter = ui.painter_at(area);
    painter.rect_filled(area, 0.0, Color32::from_gray(16));
    if let Some((_, texture)) = &view.texture {
        let rect = fitted(texture.size_vec2(), area);
        handle_input(ui, &response, rect, &mut view.zoom);
        painter.image(texture.id(), rect, view.zoom.uv(), Color32::WHITE);
    }
}

/// A live push's cameras: each topic's newest picture, at the live edge; scrubbed back, where the
/// pictures are (the recording, opened as a bag, shows them in step).
fn live_ui(
    ui: &mut egui::Ui,
    state: &AppState,
    images: &std::collections::BTreeMap<String, LiveImage>,
    dropped: &std::collections::BTreeMap<String, u64>,
    view: &mut CameraView,
) {
    if state.frame() != state.timeline().last_frame() {
        ui.weak(
            "Live pictures show at the newest frame (Back to live); the recording keeps every one, \
             shown in step when it is opened as a bag.",
        );
        return;
    }
    let height = ui.available_height() / images.len() as f32;
    for (topic, picture) in images {
        let stream = view.streams.entry(topic.clone()).or_default();
        ui.allocate_ui(egui::vec2(ui.available_width(), height), |ui| {
            ui.horizontal_wrapped(|ui| {
                ui.strong(topic);
                let dropped = dropped.get(topic).copied().unwrap_or(0);
                ui.add(
                    egui::Label::new(format!(
                        "live · picture {}{}",
                        picture.number,
                        if dropped > 0 {
                            format!(" · {dropped} came faster than shown (recorded)")
                        } else {
                            String::new()
                        }
                    ))
                    .wrap_mode(egui::TextWrapMode::Extend),
                );
            });
            match &picture.image {
                Ok(image) => upload(ui, stream, picture.number as usize, topic, image),
                Err(why) => {
                    ui.colored_label(ERROR_COLOR, format!("picture cannot be shown: {why}"));
                }
            }
            draw_texture(ui, stream);
        });
    }
}

/// The frame number and its offset from the scene frame's time, or why there is no frame.
fn caption(frame: &CameraFrame<'_>) -> String {
    match (frame.frame, frame.offset_s) {
        (Some(index), Some(offset)) => {
            let waiting = if frame.decoded.is_none() {
                " · decoding…"
            } else {
                ""
            };
            format!(
                "frame {} of {} · {:+.0} ms{waiting}",
                index + 1,
                frame.stream.len(),
                offset * 1e3
            )
        }
        _ => "no frame yet: the camera starts later".to_owned(),
    }
}

/// Wheel zooms about the pointer, a drag pans, a double-click fits the image again.
fn handle_input(ui: &egui::Ui, response: &egui::Response, rect: Rect, zoom: &mut ImageZoom) {
    if response.double_clicked() {
        *zoom = ImageZoom::default();
    }
    if response.dragged() {
        zoom.pan(response.drag_delta(), rect);
    }
    if let Some(pointer) = response.hover_pos() {
        let factor = ui.input(|i| i.zoom_delta() * (i.smooth_scroll_delta.y / 200.0).exp());
        if factor != 1.0 {
            zoom.zoom_about(factor, pointer, rect);
        }
    }
}

/// The largest rect of `size`'s aspect centred in `area`.
fn fitted(size: Vec2, area: Rect) -> Rect {
    let scale = (area.width() / size.x).min(area.height() / size.y);
    Rect::from_center_size(area.center(), size * scale)
}

fn color_image(image: &RgbaImage) -> egui::ColorImage {
    egui::ColorImage::from_rgba_unmultiplied(
        [image.width as usize, image.height as usize],
        &image.pixels,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    const RECT: Rect = Rect {
        min: Pos2::new(0.0, 0.0),
        max: Pos2::new(200.0, 100.0),
    };

    #[test]
    fn zooming_keeps_the_point_under_the_pointer() {
        let mut zoom = ImageZoom::default();
        let pointer = Pos2::new(150.0, 25.0);
        zoom.zoom_about(4.0, pointer, RECT);
        let uv = zoom.uv();
        let along = (pointer - RECT.min) / RECT.size();
        let under = uv.min + along * uv.size();
        assert!((under - Pos2::new(0.75, 0.25)).length() < 1e-6, "{under:?}");
        assert!((uv.size().x - 0.25).abs() < 1e-6);
    }

    #[test]
    fn the_view_stays_inside_the_image() {
        let mut zoom = ImageZoom::default();
        zoom.zoom_about(2.0, RECT.center(), RECT);
        zoom.pan(Vec2::new(1000.0, -1000.0), RECT);
        let uv = zoom.uv();
        assert!(
            uv.min.x.abs() < 1e-6 && (uv.max.y - 1.0).abs() < 1e-6,
            "{uv:?}"
        );
        zoom.zoom_about(0.01, RECT.center(), RECT);
        assert_eq!(zoom.zoom(), 1.0, "never smaller than the whole image");
        assert_eq!(
            zoom.uv(),
            Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0))
        );
    }

    #[test]
    fn an_image_is_fitted_keeping_its_aspect() {
        let rect = fitted(Vec2::new(1280.0, 720.0), RECT);
        assert!((rect.width() / rect.height() - 1280.0 / 720.0).abs() < 1e-4);
        assert!((rect.height() - 100.0).abs() < 1e-4 || (rect.width() - 200.0).abs() < 1e-4);
        assert_eq!(rect.center(), RECT.center());
    }
}
