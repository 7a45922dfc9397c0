//! What the camera panel shows: the selected recording's camera streams, which of them are shown,
//! and their frames, decoded off the UI thread by the core's [`FrameDecoder`].
//!
//! Once per drawn frame [`Cameras::update`] tells the decoder what is wanted: the frame at or before
//! the time of the frame the scene shows, for every shown stream, then, while playing, the frames
//! the next half second (at the playback speed) will show, so that a 30 Hz camera plays every frame
//! without the panel waiting. The panel only reads [`Cameras::shown`].

use std::collections::BTreeSet;
use std::sync::Arc;

use pushlab_core::recording::Recording;
use pushlab_core::recording::camera::{CameraStream, Decoded, FrameDecoder};

/// Seconds of playback (at 1×) prefetched ahead of the frame shown.
const PREFETCH_S: f64 = 0.5;
/// Most frames prefetched per stream, whatever the speed.
const MAX_PREFETCH: usize = 16;

/// What the camera panel can ask.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CameraCommand {
    /// Show or hide the stream called `name` (remembered by name, for every recording).
    Show { name: String, shown: bool },
}

/// One shown stream at the frame the scene shows.
pub struct CameraFrame<'a> {
    pub stream: &'a Arc<CameraStream>,
    /// The frame at or before the scene's time; `None` before the camera's first frame.
    pub frame: Option<usize>,
    /// The frame's time less the scene frame's time, seconds (≤ 0).
    pub offset_s: Option<f64>,
    /// The decoded frame, or why it cannot be shown; `None` while it is being decoded.
    pub decoded: Option<Decoded>,
}

/// The camera streams of the selected recording and their decoder.
#[derive(Default)]
pub struct Cameras {
    streams: Vec<Arc<CameraStream>>,
    /// Names of the streams the user hid, kept across recordings and restarts.
    hidden: BTreeSet<String>,
    decoder: FrameDecoder,
}

impl Cameras {
    /// Cameras hiding the streams named in `hidden` (as persisted).
    pub fn new(hidden: BTreeSet<String>) -> Self {
        Self {
            hidden,
            ..Self::default()
        }
    }

    /// Shows the cameras of `recording` (none without one); frames of the previous one are forgotten.
    pub fn select(&mut self, recording: Option<&Recording>) {
        let streams = recording.map(|r| r.cameras.clone()).unwrap_or_default();
        let same = streams.len() == self.streams.len()
            && (streams.iter().zip(&self.streams)).all(|(a, b)| Arc::ptr_eq(a, b));
        if !same {
            self.decoder.clear();
            self.streams = streams;
        }
    }

    /// Applies one command.
    pub fn apply(&mut self, command: CameraCommand) {
        match command {
            CameraCommand::Show { name, shown } => {
                if shown {
                    self.hidden.remove(&name);
                } else {
                    self.hidden.insert(name);
                }
            }
        }
    }

    /// Every stream of the selected recording, shown or not.
    pub fn streams(&self) -> &[Arc<CameraStream>] {
        &self.streams
    }

    /// Whether the stream called `name` is shown.
    pub fn is_shown(&self, name: &str) -> bool {
        !self.hidden.contains(name)
    }

    /// Whether any stream is shown (the panel appears only then).
    pub fn any_shown(&self) -> bool {
        self.streams.iter().any(|s| self.is_shown(&s.name))
    }

    /// The hidden streams' names, to persist.
    pub fn hidden(&self) -> &BTreeSet<String> {
        &self.hidden
    }

    /// Tells the decoder what is wanted for the scene frame at `time`: each shown stream's frame,
    /// then, when `playing` at `speed`, the frames ahead. Called once per drawn frame.
    pub fn update(&self, time: f64, playing: bool, speed: f64) {
        let shown = || self.streams.iter().filter(|s| self.is_shown(&s.name));
        let mut wanted: Vec<(Arc<CameraStream>, usize)> = shown()
            .filter_map(|s| Some((Arc::clone(s), s.frame_at(time)?)))
            .collect();
        if playing {
            let ahead_s = PREFETCH_S * speed.max(0.0);
            for stream in shown() {
                let ahead = stream.frames_after(time, ahead_s);
                let ahead = ahead.start..ahead.end.min(ahead.start + MAX_PREFETCH);
                wanted.extend(ahead.map(|i| (Arc::clone(stream), i)));
            }
        }
        self.decoder.want(wanted);
    }

    /// Whether a wanted frame is still being decoded (the window keeps redrawing until it lands).
    pub fn is_busy(&self) -> bool {
        self.decoder.is_busy()
    }

    /// Each shown stream at the scene frame's `time`.
    pub fn shown(&self, time: f64) -> Vec<CameraFrame<'_>> {
        (self.streams.iter())
            .filter(|s| self.is_shown(&s.name))
            .map(|stream| {
                let frame = stream.frame_at(time);
                CameraFrame {
                    stream,
                    frame,
                    offset_s: frame.map(|i| stream.times()[i] - time),
                    decoded: frame.and_then(|i| self.decoder.get(stream, i)),
                }
            })
            .collect()
    }

    /// Waits until every shown stream's frame at `time` is decoded (or up to `timeout`): for tests
    /// and benches that must see what a user would see once the frame landed.
    pub fn wait_for_shown(&self, time: f64, timeout: std::time::Duration) {
        for stream in self.streams.iter().filter(|s| self.is_shown(&s.name)) {
            if let Some(frame) = stream.frame_at(time) {
                self.decoder.wait_for(stream, frame, timeout);
            }
        }
    }
}
