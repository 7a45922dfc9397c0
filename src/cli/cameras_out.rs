//! A recording's cameras written beside its CSV as the native set's image sequences
//! (`NAME.images/frames.csv` and the images; with several cameras one folder each,
//! `NAME.images/CAMERA/`): stored JPEG and PNG frames copied byte for byte, raw ones written as PNG,
//! a frame that cannot be read left out and counted. Shared by `pushlab import` of a bag and of a
//! dataset.

use std::path::Path;
use std::sync::Arc;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::recording::camera::{CameraStream, FrameProblem, to_stored};
use pushlab_core::recording::native::images::{images_dir, write_camera};

/// Writes each camera's frames beside the push's CSV, as the native set's image sequence.
pub fn write_cameras(csv: &Path, cameras: &[Arc<CameraStream>]) -> anyhow::Result<()> {
    let folder = images_dir(csv);
    for camera in cameras {
        let dir = if cameras.len() == 1 {
            folder.clone()
        } else {
            folder.join(folder_name(&camera.name))
        };
        let bar = progress_bar(camera.len() as u64, &camera.name);
        let mut reader = camera.reader();
        let mut left_out: Vec<String> = Vec::new();
        let frames = (0..camera.len()).filter_map(|i| {
            bar.inc(1);
            let stored = reader
                .read(i)
                .and_then(|image| to_stored(image).map_err(FrameProblem::from));
            match stored {
                Ok(image) => Some((camera.times()[i], image)),
                Err(problem) => {
                    left_out.push(format!("frame {i} ({:.3} s): {problem}", camera.times()[i]));
                    None
                }
            }
        });
        let written =
            write_camera(&dir, frames).with_context(|| format!("writing {}", dir.display()))?;
        bar.finish_and_clear();
        println!(
            "camera {}: {written} frame(s) -> {}",
            camera.name,
            dir.display()
        );
        if let Some(first) = left_out.first() {
            println!(
                "warning: camera {}: {} frame(s) could not be read and were left out; the first: {first}",
                camera.name,
                left_out.len()
            );
        }
    }
    Ok(())
}

/// A folder name for a camera topic: its words joined by `_` (`/camera/color/image_raw` →
/// `camera_color_image_raw`).
fn folder_name(topic: &str) -> String {
    let name: Vec<&str> = topic
        .split(|c: char| !c.is_ascii_alphanumeric() && c != '-')
        .filter(|p| !p.is_empty())
        .collect();
    if name.is_empty() {
        "camera".to_owned()
    } else {
        name.join("_")
    }
}

/// A progress bar of frames written, on stderr, hidden when it is not a terminal.
fn progress_bar(frames: u64, camera: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(frames), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} frames ({eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(format!("camera {camera}"));
    bar
}
