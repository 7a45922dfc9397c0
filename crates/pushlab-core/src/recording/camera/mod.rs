//! What a recording's cameras saw: one stream of frames per camera, each frame at a time on the
//! recording's clock, read one at a time when shown.
//!
//! A stream knows only its frames' times and where each lies — in a bag's chunks, a file of a
//! set's image folder, a replay buffer's image array or a video file — behind [`FrameSource`], so
//! that opening a recording never reads its images and memory stays bounded by the frames shown. Reading a frame gives it as stored
//! ([`EncodedImage`]); [`decode`] makes it RGBA. A frame that cannot be read or decoded is an error
//! for that frame only: the rest play on.

mod decoder;
mod image;
mod video;

use std::path::PathBuf;
use std::sync::Arc;

pub use self::decoder::{DEFAULT_BUDGET_BYTES, Decoded, FrameDecoder};
pub use self::image::{
    EncodedImage, ImageFormat, ImageProblem, MAX_PIXELS, MAX_SIDE, RawEncoding, RgbaImage, decode,
    dimensions, sniff, to_stored,
};
pub use self::video::{FFMPEG_VARIABLE, VideoFrames, find_ffmpeg};

/// Where a stream's frames lie, and how to read them.
pub trait FrameSource: Send + Sync {
    /// A reader of the frames, holding what reading needs (open files, a decompressed chunk):
    /// one per thread that reads.
    fn reader(&self) -> Box<dyn FrameReader>;

    /// The file or folder the frames are in, for messages.
    fn location(&self) -> PathBuf;
}

/// Reads frames of one stream.
pub trait FrameReader: Send {
    /// Frame `index` as stored.
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem>;
}

/// Why a frame cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FrameProblem {
    #[error("cannot read it: {0}")]
    Unreadable(String),
    #[error(
        "its encoding `{0}` is not one pushlab reads (jpeg, png, or raw rgb8, bgr8, rgba8, bgra8, \
         mono8, mono16)"
    )]
    UnknownEncoding(String),
    #[error("the message does not decode: {0}")]
    Message(String),
    #[error(transparent)]
    Image(#[from] ImageProblem),
}

/// One camera of a recording.
#[derive(Clone)]
pub struct CameraStream {
    /// The camera's name: the topic of a bag, the folder of a set.
    pub name: String,
    /// Each frame's time, seconds on the recording's clock, increasing.
    times: Vec<f64>,
    source: Arc<dyn FrameSource>,
}

impl std::fmt::Debug for CameraStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CameraStream")
            .field("name", &self.name)
            .field("frames", &self.times.len())
            .field("location", &self.source.location())
            .finish()
    }
}

impl CameraStream {
    /// A stream of frames at `times`, increasing: frame `i` is frame `i` of `source` (each source
    /// sorts its frames by time before making its stream).
    pub fn new(name: String, times: Vec<f64>, source: Arc<dyn FrameSource>) -> Self {
        Self {
            name,
            times,
            source,
        }
    }

    /// Each frame's time, seconds on the recording's clock.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether it has no frames.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The frame shown at `time`: the last taken at or before it (within a microsecond, so that a
    /// frame stamped with the playhead's own time is not missed by rounding), or none before the
    /// first.
    pub fn frame_at(&self, time: f64) -> Option<usize> {
        let after = self.times.partition_point(|&t| t <= time + 1e-6);
        after.checked_sub(1)
    }

    /// The frames taken after `time` and at most `ahead_s` later: what to prefetch while playing.
    pub fn frames_after(&self, time: f64, ahead_s: f64) -> std::ops::Range<usize> {
        let from = self.times.partition_point(|&t| t <= time + 1e-6);
        let to = self.times.partition_point(|&t| t <= time + ahead_s + 1e-6);
        from..to.max(from)
    }

    /// A reader of the frames (see [`FrameSource::reader`]).
    pub fn reader(&self) -> Box<dyn FrameReader> {
        self.source.reader()
    }

    /// Where the frames are, for messages.
    pub fn location(&self) -> PathBuf {
        self.source.location()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Nowhere;

    impl FrameSource for Nowhere {
        fn reader(&self) -> Box<dyn FrameReader> {
            Box::new(Nothing)
        }

        fn location(&self) -> PathBuf {
            PathBuf::from("nowhere")
        }
    }

    struct Nothing;

    impl FrameReader for Nothing {
        fn read(&mut self, _: usize) -> Result<EncodedImage, FrameProblem> {
            Err(FrameProblem::Unreadable("nothing".to_owned()))
        }
    }

    #[test]
    fn the_frame_at_a_time_is_the_last_taken_at_or_before_it() {
        let stream = CameraStream::new("cam".into(), vec![0.0, 0.1, 0.2], Arc::new(Nowhere));
        assert_eq!(stream.frame_at(-0.01), None);
        assert_eq!(stream.frame_at(0.0), Some(0));
        assert_eq!(
            stream.frame_at(0.099_999_9),
            Some(1),
            "within a microsecond"
        );
        assert_eq!(stream.frame_at(0.15), Some(1));
        assert_eq!(stream.frame_at(5.0), Some(2));
    }

    #[test]
    fn the_frames_to_prefetch_are_those_after_the_one_shown() {
        let stream = CameraStream::new("cam".into(), vec![0.0, 0.1, 0.2, 0.3], Arc::new(Nowhere));
        assert_eq!(stream.frames_after(0.05, 0.2), 1..3);
        assert_eq!(stream.frames_after(0.1, 0.1), 2..3, "not the frame shown");
        assert_eq!(stream.frames_after(0.3, 1.0), 4..4);
        assert_eq!(stream.frames_after(-1.0, 0.5), 0..0);
    }
}
