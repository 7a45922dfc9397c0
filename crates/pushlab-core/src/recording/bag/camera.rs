//! A bag's cameras: the frames of `sensor_msgs/msg/CompressedImage` and `sensor_msgs/msg/Image`
//! topics, indexed in the same pass that reads the poses (only each message's stamp is read) and
//! read one at a time when shown, straight from the bag.

use std::path::PathBuf;
use std::sync::Arc;

use super::image_msg::{self, ImageKind};
use super::mcap::{Bytes, ChunkCache, MessageAt, Source, read_payload};
use crate::files::Positioned;
use crate::recording::camera::{
    CameraStream, EncodedImage, FrameProblem, FrameReader, FrameSource,
};

/// Where a bag's bytes are: its `.mcap` files, or one file held in memory.
#[derive(Clone, Debug, PartialEq)]
pub enum BagBytes {
    Files(Arc<[PathBuf]>),
    Memory { path: PathBuf, bytes: Arc<[u8]> },
}

impl Default for BagBytes {
    fn default() -> Self {
        BagBytes::Files(Arc::from([]))
    }
}

/// A camera topic's frames as a pass finds them, in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundCamera {
    pub topic: String,
    pub kind: ImageKind,
    /// Each frame's time (its header stamp, or its log time when unstamped), nanoseconds, the file
    /// of the bag it is in and where in it.
    pub frames: Vec<(u64, u32, MessageAt)>,
    /// Frames without a header stamp.
    pub unstamped: u64,
}

impl FoundCamera {
    pub fn new(topic: String, kind: ImageKind) -> Self {
        Self {
            topic,
            kind,
            frames: Vec::new(),
            unstamped: 0,
        }
    }

    /// Notes a frame from the first bytes of its message.
    pub fn note(&mut self, head: &[u8], log_time: u64, file: u32, at: MessageAt) {
        let stamp = image_msg::stamp(head).unwrap_or(0);
        let ns = if stamp == 0 {
            self.unstamped += 1;
            log_time
        } else {
            stamp
        };
        self.frames.push((ns, file, at));
    }

    /// The stream of the frames whose time, in seconds after `base_ns` less `start_s`, lies within
    /// `from..=to`, on that clock (a push's, which starts at `start_s` after `base_ns`).
    pub fn stream(
        &self,
        bag: &BagBytes,
        base_ns: u64,
        start_s: f64,
        (from, to): (f64, f64),
    ) -> CameraStream {
        let mut frames: Vec<(f64, u32, MessageAt)> = (self.frames.iter())
            .map(|&(ns, file, at)| {
                let t = (i128::from(ns) - i128::from(base_ns)) as f64 * 1e-9 - start_s;
                (t, file, at)
            })
            .filter(|(t, _, _)| (from..=to).contains(t))
            .collect();
        frames.sort_by(|a, b| a.0.total_cmp(&b.0));
        let times = frames.iter().map(|f| f.0).collect();
        let source = BagFrames {
            bag: bag.clone(),
            kind: self.kind,
            frames: frames.into_iter().map(|(_, file, at)| (file, at)).collect(),
        };
        CameraStream::new(self.topic.clone(), times, Arc::new(source))
    }
}

/// A camera topic's frames in a bag, in the stream's order.
struct BagFrames {
    bag: BagBytes,
    kind: ImageKind,
    frames: Vec<(u32, MessageAt)>,
}

impl FrameSource for BagFrames {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(BagFrameReader {
            bag: self.bag.clone(),
            kind: self.kind,
            frames: self.frames.clone(),
            files: Vec::new(),
            cache: ChunkCache::default(),
            cached_file: None,
        })
    }

    fn location(&self) -> PathBuf {
        match &self.bag {
            BagBytes::Files(files) => files.first().cloned().unwrap_or_default(),
            BagBytes::Memory { path, .. } => path.clone(),
        }
    }
}

struct BagFrameReader {
    bag: BagBytes,
    kind: ImageKind,
    frames: Vec<(u32, MessageAt)>,
    /// The bag's files, opened when first read.
    files: Vec<Option<Positioned>>,
    /// The last decompressed chunk, and the file it is of.
    cache: ChunkCache,
    cached_file: Option<u32>,
}

impl FrameReader for BagFrameReader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        let &(file, at) = self
            .frames
            .get(index)
            .ok_or_else(|| FrameProblem::Unreadable(format!("there is no frame {index}")))?;
        if self.cached_file != Some(file) {
            self.cache = ChunkCache::default();
            self.cached_file = Some(file);
        }
        let unreadable = |e: String| FrameProblem::Unreadable(e);
        let payload = match &self.bag {
            BagBytes::Memory { bytes, .. } => read_payload(&Bytes(bytes), &at, &mut self.cache)
                .map_err(|p| unreadable(p.to_string()))?,
            BagBytes::Files(paths) => {
                let slot = file as usize;
                let path = paths
                    .get(slot)
                    .ok_or_else(|| unreadable(format!("the bag has no file {slot}")))?;
                if self.files.len() <= slot {
                    self.files.resize_with(slot + 1, || None);
                }
                if self.files[slot].is_none() {
                    let source = Positioned::open(path)
                        .map_err(|e| unreadable(format!("{}: {e}", path.display())))?;
                    self.files[slot] = Some(source);
                }
                let source: &dyn Source = self.files[slot]
                    .as_ref()
                    .ok_or_else(|| unreadable(format!("{} is not open", path.display())))?;
                read_payload(source, &at, &mut self.cache)
                    .map_err(|p| unreadable(format!("{}: {p}", path.display())))?
            }
        };
        image_msg::decode(self.kind, &payload).map(|(_, image)| image)
    }
}
