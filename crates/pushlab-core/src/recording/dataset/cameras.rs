//! Each episode's cameras: a replay buffer's image arrays (`data/img`, read from the buffer's
//! chunks), a LeRobot dataset's image features (pictures in its parquet files) and its video
//! features (MP4 files decoded by ffmpeg), each frame at the time of its episode's frame — read
//! only when shown.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::DatasetError;
use super::lerobot::ParquetImages;
use super::table::{DatasetFormat, DatasetTable};
use super::zarr_frames::ImageArray;
use crate::recording::camera::{CameraStream, VideoFrames, find_ffmpeg};

/// What every episode's cameras are made from, opened once per dataset.
pub struct DatasetCameras {
    arrays: Vec<Arc<ImageArray>>,
    /// Where ffmpeg is (or why not), looked up once when the dataset has videos.
    ffmpeg: Option<Result<PathBuf, String>>,
}

impl DatasetCameras {
    /// Opens a replay buffer's image arrays (an error names the array's `.zarray` when its frames
    /// are not whole along time) and finds ffmpeg for a LeRobot dataset's videos.
    pub fn open(dataset: &Path, table: &DatasetTable) -> Result<Self, DatasetError> {
        let arrays = if table.format == DatasetFormat::ReplayBuffer {
            (table.cameras.iter())
                .map(|(name, _)| {
                    ImageArray::open(&dataset.join("data").join(name), name).map(Arc::new)
                })
                .collect::<Result<_, _>>()?
        } else {
            Vec::new()
        };
        let ffmpeg = (!table.videos.is_empty()).then(find_ffmpeg);
        Ok(Self { arrays, ffmpeg })
    }

    /// The cameras of the table's episode `episode`: its rows of each image array and its span of
    /// each video, at its frames' times.
    pub fn of_episode(&self, table: &DatasetTable, episode: usize) -> Vec<Arc<CameraStream>> {
        let Some(rows) = table.episodes.get(episode) else {
            return Vec::new();
        };
        let times = frame_times(table, rows);
        let images = (self.arrays.iter())
            .map(|images| Arc::new(images.episode_camera(rows.start, times.clone())));
        let videos = (table.videos.iter()).filter_map(|video| {
            let span = video.episodes.get(episode)?;
            let ffmpeg = self.ffmpeg.clone()?;
            let file_times = times.iter().map(|t| span.from_s + t).collect();
            let frames = VideoFrames::new(
                span.file.clone(),
                video.size_px,
                table.fps,
                file_times,
                ffmpeg,
            );
            let stream = CameraStream::new(video.name.clone(), times.clone(), Arc::new(frames));
            Some(Arc::new(stream))
        });
        let pictures = (table.images.iter()).filter_map(|feature| {
            let span = feature.episodes.get(episode)?;
            let source = ParquetImages::new(
                span.file.clone(),
                feature.name.clone(),
                span.first_row,
                rows.len(),
            );
            let stream = CameraStream::new(feature.name.clone(), times.clone(), Arc::new(source));
            Some(Arc::new(stream))
        });
        images.chain(pictures).chain(videos).collect()
    }
}

/// Each frame's time in its episode, seconds.
fn frame_times(table: &DatasetTable, rows: &Range<usize>) -> Vec<f64> {
    rows.clone()
        .map(|row| table.time(row, rows.start))
        .collect()
}
