//! Files the app writes and reads besides recordings: PNG snapshots of a window region, the losses as
//! CSV, label exports and model files. Every write goes to a temporary file that is renamed into place, so a crash
//! never leaves half a file under the user's chosen name.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use eframe::egui;
use pushlab_core::labels::export as label_export;
use pushlab_core::labels::pipeline::{key_of, labels_file_beside};
use pushlab_core::model_file::ModelFile;

use super::dialogs::LabelExportFormat;
use super::state::AppState;

/// Writes `bytes` to `path` atomically (see `pushlab_core::atomic_file`).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    pushlab_core::atomic_file::write_atomically(path, bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}

/// Exports the labels file of the selected recording's folder (every recording in it, with frame
/// times from the open recordings) as CSV or JSON. Returns the number of segment and event rows.
pub fn export_labels(
    state: &AppState,
    path: &Path,
    format: LabelExportFormat,
) -> anyhow::Result<usize> {
    let target = state
        .label_target()
        .context("select a recording whose labels to export")?;
    let document = state
        .labels
        .document(&target.document)
        .with_context(|| format!("{} could not be read", target.document.display()))?;
    let times: BTreeMap<String, Vec<f64>> = state
        .session
        .recordings()
        .filter(|(_, r)| labels_file_beside(&r.source) == target.document)
        .filter_map(|(_, r)| {
            let key = key_of(&r.source)?;
            Some((key, r.trajectory.frames.iter().map(|f| f.time).collect()))
        })
        .collect();
    let set = document.set();
    let rows = label_export::rows(set, &times)?.len();
    let text = match format {
        LabelExportFormat::Csv => label_export::to_csv(set, &times)?,
        LabelExportFormat::Json => label_export::to_json(set, &times)?,
    };
    label_export::write(path, &text)?;
    Ok(rows)
}

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
    write_atomic(path, &png)
}

/// The per-frame losses and θ of the selected recording as CSV: one row per sample, online values
/// empty where nothing was learned yet. Returns the CSV text.
///
/// The run keeps its losses in `f32` for drawing; the export predicts every frame again (with
/// `θ_online(0)`, and with θ at each learned frame: the step that was learned there) to write them
/// at full precision.
pub fn losses_csv(state: &AppState) -> Option<String> {
    let run = state.run.as_ref()?;
    let recording = state.recording()?;
    let frames = &recording.trajectory.frames;
    let t0 = frames.first().map_or(0.0, |f| f.time);
    let mut csv = String::from(
        "frame,time,fixed_loss_pos,fixed_loss_rot,online_loss_pos,online_loss_rot,com_offset_x,com_offset_y,h\n",
    );
    for k in 0..run.sample_count() {
        let time = frames.get(k).map_or(f64::NAN, |f| f.time - t0);
        let fixed = run.evaluate_fixed(k)?.loss;
        let _ = write!(csv, "{k},{time},{},{}", fixed.pos(), fixed.rot);
        match run.learned().get(k).copied().flatten() {
            Some(_) => {
                let online = run.evaluate(k)?.loss;
                let _ = write!(csv, ",{},{}", online.pos(), online.rot);
            }
            None => csv.push_str(",,"),
        }
        if k <= run.frontier() {
            let theta = run.theta_at(k);
            let _ = writeln!(
                csv,
                ",{},{},{}",
                theta.com_offset[0], theta.com_offset[1], theta.h
            );
        } else {
            csv.push_str(",,,\n");
        }
    }
    Some(csv)
}

/// Saves [`losses_csv`]; returns the number of data rows.
pub fn save_losses_csv(state: &AppState, path: &Path) -> anyhow::Result<usize> {
    let csv = losses_csv(state).context("no recording selected: nothing to export")?;
    write_atomic(path, csv.as_bytes())?;
    Ok(csv.lines().count().saturating_sub(1))
}

/// The bundled pretrained model, if the build ships one.
pub fn default_model_path() -> Option<PathBuf> {
    let candidates = [
        PathBuf::from("assets/default-model.json"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default-model.json"),
    ];
    candidates.into_iter().find(|p| p.is_file())
}

/// Loads a model file and restarts online learning with it.
pub fn load_model(state: &mut AppState, path: &Path) -> anyhow::Result<()> {
    let file = ModelFile::load(path)?;
    state.use_model_file(file, path.display().to_string());
    Ok(())
}

/// Saves the combined model in use (and the pure-network baseline, if any) as a model file.
pub fn save_model(state: &AppState, path: &Path) -> anyhow::Result<()> {
    let combined = state
        .models
        .combined
        .as_ref()
        .context("no trained model to save: train one or load a model file first")?;
    let file = ModelFile {
        combined: combined.clone(),
        pure_nn: state.models.pure_nn.as_deref().cloned(),
        training: state.models.training.clone(),
    };
    file.save(path)?;
    Ok(())
}
