//! A replay buffer's image array (`data/img`: frames × height × width × 3 bytes, Diffusion Policy's
//! 96 × 96 renders of the arena) as each episode's camera: frames read when shown, one decoded
//! chunk kept per reader, so memory stays a chunk however long the buffer.

use std::path::PathBuf;
use std::sync::Arc;

use super::error::DatasetError;
use super::problem::DatasetProblem;
use super::zarr::ZarrArray;
use crate::recording::camera::{
    CameraStream, EncodedImage, FrameProblem, FrameReader, FrameSource, ImageFormat, RawEncoding,
};

/// An image array checked to hold whole frames per chunk, RGB or grey bytes.
#[derive(Debug)]
pub struct ImageArray {
    array: ZarrArray,
    name: String,
    width: u32,
    height: u32,
    encoding: RawEncoding,
}

impl ImageArray {
    /// The image array in `dir` (named `name` in the buffer); an error names its `.zarray` when its
    /// frames are not bytes of height × width (× 3), or a chunk splits a frame.
    pub fn open(dir: &std::path::Path, name: &str) -> Result<Self, DatasetError> {
        let array = ZarrArray::open(dir)?;
        let fail = |why: String| DatasetError::Problem {
            path: dir.join(".zarray"),
            problem: DatasetProblem::Field {
                field: "shape".into(),
                why,
            },
        };
        let encoding = match array.shape.as_slice() {
            [_, _, _, 3] => RawEncoding::Rgb8,
            [_, _, _] => RawEncoding::Mono8,
            shape => {
                return Err(fail(format!(
                    "{shape:?}, expected frames × height × width (× 3) for images"
                )));
            }
        };
        if !array.dtype.is_byte() {
            return Err(fail("images must be bytes (dtype |u1)".into()));
        }
        if array.chunk_shape()[1..] != array.shape[1..] {
            return Err(fail(format!(
                "chunks {:?} split a frame; pushlab reads image arrays chunked along time only",
                array.chunk_shape()
            )));
        }
        let side = |n: usize| u32::try_from(n).map_err(|_| fail(format!("a side of {n} pixels")));
        Ok(Self {
            width: side(array.shape[2])?,
            height: side(array.shape[1])?,
            encoding,
            name: name.to_owned(),
            array,
        })
    }

    /// The camera of the episode whose frames are rows `first..` at `times`.
    pub fn episode_camera(self: &Arc<Self>, first: usize, times: Vec<f64>) -> CameraStream {
        let source = EpisodeFrames {
            images: Arc::clone(self),
            first,
        };
        CameraStream::new(self.name.clone(), times, Arc::new(source))
    }

    fn frame_bytes(&self) -> usize {
        self.array.width()
    }
}

/// One episode's rows of an image array.
struct EpisodeFrames {
    images: Arc<ImageArray>,
    first: usize,
}

impl FrameSource for EpisodeFrames {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(Reader {
            images: Arc::clone(&self.images),
            first: self.first,
            chunk: None,
        })
    }

    fn location(&self) -> PathBuf {
        self.images.array.dir().to_path_buf()
    }
}

struct Reader {
    images: Arc<ImageArray>,
    first: usize,
    /// The last chunk decoded: its index along time and its bytes.
    chunk: Option<(usize, Vec<u8>)>,
}

impl FrameReader for Reader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        let images = &self.images;
        let row = self.first + index;
        if row >= images.array.shape[0] {
            return Err(FrameProblem::Unreadable(format!(
                "row {row} is past the array's {} rows",
                images.array.shape[0]
            )));
        }
        let rows_per_chunk = images.array.chunk_shape()[0];
        let chunk_index = row / rows_per_chunk;
        if self.chunk.as_ref().is_none_or(|(i, _)| *i != chunk_index) {
            let bytes = (images.array.read_time_chunk(chunk_index))
                .map_err(|e| FrameProblem::Unreadable(e.to_string()))?;
            self.chunk = Some((chunk_index, bytes));
        }
        let Some((_, bytes)) = &self.chunk else {
            return Err(FrameProblem::Unreadable("no chunk".into()));
        };
        let size = images.frame_bytes();
        let at = (row - chunk_index * rows_per_chunk) * size;
        let frame = bytes.get(at..at + size).ok_or_else(|| {
            FrameProblem::Unreadable(format!("chunk {chunk_index} is shorter than its rows"))
        })?;
        let channels = if images.encoding == RawEncoding::Rgb8 {
            3
        } else {
            1
        };
        Ok(EncodedImage {
            format: ImageFormat::Raw {
                encoding: images.encoding,
                width: images.width,
                height: images.height,
                step: images.width * channels,
                big_endian: false,
            },
            bytes: frame.to_vec(),
        })
    }
}
