//! A push rendered as a video (`pushlab render`): the recording played with the model, learning
//! online as the app does (the app's own run, stepped frame by frame), each frame of the video the
//! app's scene at the recording's frame shown at that time — drawn by the app's painting code,
//! tessellated by egui and painted on the CPU ([`raster`]) — and written as GIF, MP4 or WebM
//! ([`video`]).

mod frames;
mod palette;
pub mod raster;
pub mod video;

use std::ops::Range;
use std::path::{Path, PathBuf};

use eframe::egui;

pub use self::frames::SceneFrames;
use self::video::VideoWriter;
use crate::app::colors;
use crate::app::state::commands::video_export::VideoWork;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command, SessionCommand};

/// How a push is rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Width and height, pixels.
    pub size: [usize; 2],
    /// Frames of the video a second.
    pub fps: f64,
    /// Seconds of the recording a second of video.
    pub speed: f64,
    /// The recording's frames to render; `None`: all.
    pub frames: Option<Range<usize>>,
    /// The app's loss and θ plots below the scene.
    pub with_plots: bool,
    /// Light (paper, projector) or dark (screen) colours, the app's own for each.
    pub theme: egui::Theme,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            size: [1280, 720],
            fps: 30.0,
            speed: 1.0,
            frames: None,
            with_plots: false,
            theme: egui::Theme::Dark,
        }
    }
}

/// The recording's frame each video frame shows: the last frame at or before the video frame's
/// time, `speed` seconds of recording a second, from the range's first frame to its last.
pub fn frames_shown(times: &[f64], range: Range<usize>, fps: f64, speed: f64) -> Vec<usize> {
    let range = range.start.min(times.len())..range.end.min(times.len());
    let (Some(&start), Some(&end)) = (times.get(range.start), times.get(range.end.wrapping_sub(1)))
    else {
        return Vec::new();
    };
    let count = ((end - start) / speed * fps).floor() as usize + 1;
    let mut shown = Vec::with_capacity(count);
    let mut k = range.start;
    for i in 0..count {
        let t = start + i as f64 * speed / fps;
        while k + 1 < range.end && times[k + 1] <= t + 1e-9 {
            k += 1;
        }
        shown.push(k);
    }
    shown
}

/// Renders the recording `state` shows to `out`, telling `progress` each frame done (of all) and
/// stopping, with nothing written, when it says so.
pub fn render(
    state: AppState,
    out: &Path,
    options: &RenderOptions,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> anyhow::Result<PathBuf> {
    let times: Vec<f64> = match state.recording() {
        Some(recording) => recording.trajectory.frames.iter().map(|f| f.time).collect(),
        None => anyhow::bail!("no recording to render"),
    };
    let range = options.frames.clone().unwrap_or(0..times.len());
    if range.start >= times.len() || range.is_empty() {
        anyhow::bail!(
            "--frames {}..{}: the recording has frames 0..{}",
            range.start,
            range.end,
            times.len()
        );
    }
    let shown = frames_shown(&times, range, options.fps, options.speed);
    let palette = colors::of_theme(options.theme);
    let mut writer = VideoWriter::create(out, options.size, options.fps, palette)?;
    let mut scene = SceneFrames::new(state, options.size, options.with_plots, options.theme);
    for (i, &k) in shown.iter().enumerate() {
        scene.show(k);
        writer.push(scene.draw())?;
        if !progress(i + 1, shown.len()) {
            anyhow::bail!("stopped: nothing written");
        }
    }
    writer.finish()
}

/// File → Export video of this push…: the work that renders the push `state` shows to `path` with
/// `options`, as on screen — its settings (layers, online learning), models, and θ where its run
/// went on from an earlier push — in a state of its own on the worker; why not, in words.
pub fn work_for(
    state: &AppState,
    path: PathBuf,
    options: RenderOptions,
) -> Result<VideoWork, String> {
    let source = (state.recording())
        .map(|r| r.source.clone())
        .ok_or("no push is shown")?;
    video::Container::of(&path).map_err(|e| format!("{e:#}"))?;
    let persisted = state.persisted();
    let models = state.models().clone();
    let carried = state.run().and_then(|run| run.carried());
    Ok(Box::new(move |job| {
        let mut state = AppState::new(persisted, models);
        state.open_blocking(&[source]);
        if let Some(carried) = carried {
            state.go_on_as(carried);
        }
        let mut progress = |done: usize, all: usize| {
            job.set_progress(done as f32 / all.max(1) as f32);
            !job.is_cancelled()
        };
        Some(render(state, &path, &options, &mut progress).map_err(|e| format!("{e:#}")))
    }))
}

/// `--carry-theta`: plays every push opened before `recording` (in the order they were opened,
/// as `pushlab eval --carry-theta` takes its pushes) to its end, learning, and shows `recording`,
/// whose run then goes on from the θ they ended with — the app's carry θ, which must be on in
/// `state`. Returns the pushes played; an error when `recording` is not open.
pub fn carry_to(state: &mut AppState, recording: &Path) -> anyhow::Result<usize> {
    let same = |a: &Path| a.canonicalize().ok() == recording.canonicalize().ok();
    let ids: Vec<_> = (state.session().recordings())
        .map(|(id, r)| (id, same(&r.source), r.trajectory.len()))
        .collect();
    let Some(at) = ids.iter().position(|(_, is, _)| *is) else {
        anyhow::bail!("{} is not among the pushes opened", recording.display());
    };
    for &(id, _, frames) in &ids[..at] {
        state.apply(Command::Session(SessionCommand::Select(id)));
        for _ in 0..frames {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
    }
    state.apply(Command::Session(SessionCommand::Select(ids[at].0)));
    Ok(at)
}
