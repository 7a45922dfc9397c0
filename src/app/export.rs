//! Files the window writes and finds: PNG snapshots of a window region (egui's screenshot, so
//! here rather than in the state, whose `files` writes the losses, labels and models) and the
//! bundled model. Writes go to a temporary file renamed into place, so a crash never leaves half a
//! file under the user's chosen name.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use eframe::egui;

/// Crops `rect` (points) out of a window screenshot and saves it as PNG.
pub fn save_region_png(
    image: &egui::ColorImage,
    rect: egui::Rect,
    pixels_per_point: f32,
    path: &Path,
) -> anyhow::Result<()> {
    let region = image.region(&rect, Some(pixels_per_point));
    let [w, h] = region.size;
    let rgba: Vec<u8> = region.pixels.iter().flat_map(|c| c.to_array()).collect();
    let buffer = image::RgbaImage::from_raw(w as u32, h as u32, rgba)
        .context("screenshot region has an inconsistent size")?;
    let mut png = Vec::new();
    buffer
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .context("cannot encode PNG")?;
    pushlab_core::files::write_atomically(path, &png)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// The bundled pretrained model, if the build ships one.
pub fn default_model_path() -> Option<PathBuf> {
    let path = super::platform::bundled_root().join("assets/default-model.json");
    pushlab_core::files::is_file(&path).then_some(path)
}
