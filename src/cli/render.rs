//! `pushlab render RECORDING --out push.gif|mp4|webm`: the push as a video, learning online as the
//! app does, with indicatif progress; Ctrl-C stops it and leaves no file.

use std::ops::Range;
use std::path::PathBuf;

use clap::Args;
use eframe::egui;
use indicatif::{ProgressBar, ProgressStyle};

use pushlab::app::render::{RenderOptions, carry_to, render};
use pushlab::app::state::Persisted;

use super::exit::Failure;
use super::experiment::args::{OnlineArgs, offset_xy, positive_real};

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The recording: a set's CSV (or a folder: its first push), a bag, a dataset.
    pub recording: PathBuf,
    /// The video to write: .gif, .mp4 (H.264) or .webm (VP9); MP4 and WebM need ffmpeg.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// A model file; default: the bundled model.
    #[arg(long, value_name = "FILE")]
    pub model: Option<PathBuf>,
    /// Width and height, pixels.
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = size)]
    pub size: [usize; 2],
    /// Frames of video a second.
    #[arg(long, value_name = "FPS", default_value_t = 30.0, value_parser = positive_real)]
    pub fps: f64,
    /// Seconds of the recording a second of video.
    #[arg(long, value_name = "S", default_value_t = 1.0, value_parser = positive_real)]
    pub speed: f64,
    /// The recording's frames to render, `A..B` (B not included); default: all.
    #[arg(long, value_name = "A..B", value_parser = frame_range)]
    pub frames: Option<Range<usize>>,
    /// The scene's layers drawn, by short name, comma-separated (default: the app's): true-now,
    /// true-target, online, fixed, physics, pure-nn, what-if, controller, com, ellipse, true-com,
    /// best-com, com-label, contact, next-pushes, robot-path, trails, grid.
    #[arg(long, value_name = "NAMES")]
    pub layers: Option<String>,
    /// The app's loss and θ plots below the scene, growing as the push is learned.
    #[arg(long)]
    pub with_plots: bool,
    /// `dark` (the app's screen colours) or `light` (dark strokes on white, for slides and paper).
    #[arg(long, value_name = "THEME", default_value = "dark", value_parser = theme)]
    pub theme: egui::Theme,
    /// Go on from the θ learned along the pushes before RECORDING in its folder (played first, in
    /// order), as `pushlab eval --carry-theta` goes on from one push to the next.
    #[arg(long)]
    pub carry_theta: bool,
    /// Start believing the COM this far from θ_online(0)'s (object frame, metres, e.g. 0.02,0), as
    /// `pushlab eval --start-com-shift`: the estimate sliding back to where the data puts it.
    #[arg(long, value_name = "X,Y", value_parser = offset_xy, allow_hyphen_values = true)]
    pub start_com_shift: Option<[f64; 2]>,
    #[command(flatten)]
    pub online: OnlineArgs,
}

fn theme(text: &str) -> Result<egui::Theme, String> {
    match text {
        "dark" => Ok(egui::Theme::Dark),
        "light" => Ok(egui::Theme::Light),
        _ => Err(format!("{text:?}: expected dark or light")),
    }
}

fn size(text: &str) -> Result<[usize; 2], String> {
    let parsed = text
        .split_once('x')
        .and_then(|(w, h)| Some([w.parse().ok()?, h.parse().ok()?]));
    match parsed {
        Some([w, h]) if (16..=7680).contains(&w) && (16..=4320).contains(&h) => Ok([w, h]),
        _ => Err(format!(
            "{text}: expected WIDTHxHEIGHT in pixels, 16 to 7680 by 16 to 4320 (1280x720)"
        )),
    }
}

fn frame_range(text: &str) -> Result<Range<usize>, String> {
    let parsed = text
        .split_once("..")
        .and_then(|(a, b)| Some(a.parse().ok()?..b.parse().ok()?));
    match parsed {
        Some(range) if !range.is_empty() => Ok(range),
        _ => Err(format!("{text}: expected frames A..B with A < B (0..200)")),
    }
}

pub fn run(args: &RenderArgs) -> Result<(), Failure> {
    let defaults = Persisted::default();
    let layers = match &args.layers {
        Some(names) => defaults
            .layers
            .only(names)
            .map_err(|why| Failure::Usage(anyhow::anyhow!("--layers: {why}")))?,
        None => defaults.layers.clone(),
    };
    let persisted = Persisted {
        online: args.online.config(),
        layers,
        carry_theta: args.carry_theta,
        start_com_shift: args.start_com_shift,
        ..defaults
    };
    // Carrying θ, the pushes before it in its folder are opened and played first.
    let open = match args.recording.parent().filter(|_| args.carry_theta) {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        Some(_) => PathBuf::from("."),
        None => args.recording.clone(),
    };
    let mut state = pushlab::app::initial_state(std::slice::from_ref(&open), persisted);
    if state.recording().is_none() {
        let problems: Vec<&str> = (state.session().problems.iter())
            .map(|p| p.message.as_str())
            .collect();
        return Err(Failure::Failed(anyhow::anyhow!(
            "{}: no recording opened: {}",
            args.recording.display(),
            problems.join("; ")
        )));
    }
    if let Some(model) = &args.model {
        state.load_model(model)?;
    }
    if args.carry_theta {
        let played = carry_to(&mut state, &args.recording)?;
        eprintln!("--carry-theta: went on from the θ learned along {played} push(es) before it");
    }
    let options = RenderOptions {
        size: args.size,
        fps: args.fps,
        speed: args.speed,
        frames: args.frames.clone(),
        with_plots: args.with_plots,
        theme: args.theme,
    };
    let bar = ProgressBar::new(0);
    if let Ok(style) = ProgressStyle::with_template(
        "rendering [{bar:30}] frame {pos}/{len} ({elapsed}, {eta} left)",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    let cancel = super::interrupt::cancel_flag();
    let written = render(state, &args.out, &options, &mut |done, all| {
        bar.set_length(all as u64);
        bar.set_position(done as u64);
        !cancel.load(std::sync::atomic::Ordering::Relaxed)
    });
    bar.finish_and_clear();
    let written = written?;
    println!("wrote {}", written.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use clap::{Args, Command};

    use super::RenderArgs;
    use pushlab::app::state::playback::layers::NAMED;

    #[test]
    fn the_help_lists_every_layer_by_its_short_name() {
        let command = RenderArgs::augment_args(Command::new("render"));
        let help = command
            .get_arguments()
            .find(|a| a.get_id() == "layers")
            .and_then(|a| a.get_help())
            .map(|h| h.to_string().replace('\n', " "))
            .unwrap_or_default();
        for (name, _) in NAMED {
            assert!(
                help.contains(&format!(" {name},")) || help.ends_with(&format!(" {name}")),
                "--layers' help lacks {name}: {help}"
            );
        }
    }
}
