//! LeRobot datasets (`lerobot/pusht`, `lerobot/pusht_keypoints` and the like): a folder whose
//! `meta/info.json` names the codebase version, the frame rate and the features, with the frames in
//! parquet files. v2.0 and v2.1 keep one file per episode (`data/chunk-000/episode_000000.parquet`,
//! the episodes listed in `meta/episodes.jsonl`); v3.0 concatenates episodes in larger files
//! (`data/chunk-000/file-000.parquet`, which file each episode is in listed in
//! `meta/episodes/chunk-000/file-000.parquet`). Either way every row carries its `episode_index`,
//! which gives the episodes' rows ([`episodes::Runs`]: each episode's rows together, agreeing with
//! the metadata), and its `timestamp`, which gives the frames' times.
//!
//! Every numeric feature of `info.json` with its shape is read ([`parquet_rows`], through the
//! parquet crate's record API: no arrow); image and video features are listed as cameras — an image
//! feature's pictures, in the parquet files, read when shown ([`parquet_images`]) — and each
//! video feature's file and start time for every episode is found ([`super::VideoFeature`]: v2
//! one file per episode, v3.0 the file and `from_timestamp` its episode metadata gives), so that
//! the episodes' cameras play its frames (decoded by ffmpeg when shown, `camera::VideoFrames`).

mod episodes;
mod info;
mod parquet_images;
mod parquet_rows;
mod parquet_source;

use std::collections::{BTreeSet, HashMap};
use std::ops::Range;
use std::path::{Path, PathBuf};

use self::episodes::{EPISODES_DIR, EPISODES_JSONL, Listed, Runs, parquet_files, whole_number};
use self::info::{INFO_FILE, Info, Layout};
use self::parquet_rows::{Wanted, append_file};
use super::error::DatasetError;
use super::problem::DatasetProblem;
use super::table::{DatasetFormat, DatasetTable, Feature, ImageFeature, RowSpan, VideoSpan};
use crate::recording::progress::Progress;

pub use self::info::SUPPORTED;
pub(super) use self::parquet_images::ParquetImages;

/// The column that says which episode a row is of.
const EPISODE_INDEX: &str = "episode_index";
/// The column of each frame's time in its episode, seconds.
const TIMESTAMP: &str = "timestamp";

/// Whether `dir` holds a LeRobot dataset: a `meta/info.json` with a `codebase_version`, whichever
/// (a version pushlab does not read is refused by [`read`], naming it).
pub fn is_lerobot(dir: &Path) -> bool {
    info::version_of(dir).is_some()
}

/// Bytes of the parquet files that will be read, for the progress bar.
pub fn bytes(dir: &Path) -> u64 {
    [dir.join("data"), dir.join(EPISODES_DIR)]
        .iter()
        .flat_map(|folder| parquet_files(folder))
        .filter_map(|file| crate::files::metadata(&file).ok())
        .map(|m| m.len)
        .sum()
}

/// Reads the dataset's numeric features and its episodes.
pub fn read(dir: &Path, progress: &dyn Progress) -> Result<DatasetTable, DatasetError> {
    let info = info::read(dir)?;
    let wanted: Vec<Wanted> = (info.features.iter())
        .map(|f| Wanted {
            name: f.name.clone(),
            width: f.width,
            expected: f.expected(),
            wanted_by: format!("{INFO_FILE} lists as a feature"),
        })
        .collect();
    let episode_column = (info.features.iter())
        .position(|f| f.name == EPISODE_INDEX && f.width == 1)
        .ok_or_else(|| DatasetError::Problem {
            path: dir.join(INFO_FILE),
            problem: DatasetProblem::Field {
                field: format!("features.{EPISODE_INDEX}"),
                why: "missing, expected LeRobot's episode index of every frame (int64, shape [1])"
                    .into(),
            },
        })?;
    let mut columns = vec![Vec::new(); wanted.len()];
    let reading = Reading {
        dir,
        info: &info,
        wanted: &wanted,
        episode_column,
        progress,
    };
    let episodes = match info.layout {
        Layout::FilePerEpisode => reading.file_per_episode(&mut columns)?,
        Layout::ConcatenatedEpisodes => reading.concatenated(&mut columns)?,
    };
    let mut videos = info.videos.clone();
    for (k, video) in videos.iter_mut().enumerate() {
        video.episodes = (episodes.iter())
            .filter_map(|episode| episode.videos.get(k).cloned())
            .collect();
    }
    let images = (info.images.iter())
        .map(|name| ImageFeature {
            name: name.clone(),
            episodes: episodes.iter().map(|e| e.data.clone()).collect(),
        })
        .collect();
    let episodes: Vec<Range<usize>> = episodes.into_iter().map(|episode| episode.rows).collect();
    let features: Vec<Feature> = (info.features.iter().zip(columns))
        .map(|(feature, values)| Feature {
            name: feature.name.clone(),
            width: feature.width,
            values,
        })
        .collect();
    let times = (features.iter())
        .find(|f| f.name == TIMESTAMP && f.width == 1)
        .map(|f| f.values.clone());
    let frames = episodes.iter().map(ExactSizeIterator::len).sum();
    let notes = info.disagreements(episodes.len(), frames);
    Ok(DatasetTable {
        format: DatasetFormat::LeRobot(info.version),
        features,
        episodes,
        fps: info.fps,
        times,
        cameras: info.cameras,
        videos,
        images,
        notes,
    })
}

/// An episode's rows in the table, where they are in the parquet files, and where its frames of
/// each video feature are.
struct EpisodeRows {
    rows: Range<usize>,
    data: RowSpan,
    videos: Vec<VideoSpan>,
}

/// One read of a dataset's parquet files into the columns of `wanted`.
struct Reading<'a> {
    dir: &'a Path,
    info: &'a Info,
    wanted: &'a [Wanted],
    /// Which of `wanted` is `episode_index`.
    episode_column: usize,
    progress: &'a dyn Progress,
}

impl Reading<'_> {
    /// The video file of feature `video` (one of the info's videos) with these template fields.
    fn video_file(&self, video: &str, fields: &[(&str, usize)]) -> Result<PathBuf, DatasetError> {
        let template = (self.info.videos.iter())
            .find(|v| v.name == video)
            .map(|v| v.path_template.replace("{video_key}", video))
            .unwrap_or_default();
        info::file_in(self.dir, &template, "video_path", fields).map_err(|problem| {
            DatasetError::Problem {
                path: self.dir.join(INFO_FILE),
                problem,
            }
        })
    }

    /// The data file of `data_path` with these template fields.
    fn data_file(&self, fields: &[(&str, usize)]) -> Result<std::path::PathBuf, DatasetError> {
        info::file_in(self.dir, &self.info.data_path, "data_path", fields).map_err(|problem| {
            DatasetError::Problem {
                path: self.dir.join(INFO_FILE),
                problem,
            }
        })
    }

    /// v2.x: each listed episode's own file, holding its rows only, as many as listed.
    fn file_per_episode(&self, columns: &mut [Vec<f64>]) -> Result<Vec<EpisodeRows>, DatasetError> {
        let listed = episodes::read_jsonl(self.dir)?;
        let mut episodes = Vec::with_capacity(listed.len());
        let mut first = 0;
        for Listed { index, length, .. } in listed {
            let file = self.data_file(&[
                ("episode_chunk", index / self.info.chunks_size),
                ("episode_index", index),
            ])?;
            let rows = append_file(&file, self.wanted, columns, self.progress)?;
            let fail = |problem| DatasetError::Problem {
                path: file.clone(),
                problem,
            };
            let indexes = &columns[self.episode_column][first..];
            if let Some((row, &value)) =
                (indexes.iter().enumerate()).find(|&(_, &value)| whole_number(value) != Some(index))
            {
                return Err(fail(DatasetProblem::Column {
                    column: EPISODE_INDEX.into(),
                    row,
                    found: value.to_string(),
                    expected: format!("{index}, the episode whose file this is"),
                }));
            }
            if rows != length {
                return Err(fail(DatasetProblem::Episodes(format!(
                    "episode {index} has {rows} rows, but {EPISODES_JSONL} says its length is \
                     {length}"
                ))));
            }
            if rows == 0 {
                return Err(fail(DatasetProblem::Episodes(format!(
                    "episode {index} has no rows, expected at least one frame"
                ))));
            }
            let chunk = ("episode_chunk", index / self.info.chunks_size);
            let videos = (self.info.videos.iter())
                .map(|video| {
                    let file = self.video_file(&video.name, &[chunk, ("episode_index", index)])?;
                    Ok(VideoSpan { file, from_s: 0.0 })
                })
                .collect::<Result<_, DatasetError>>()?;
            episodes.push(EpisodeRows {
                rows: first..first + rows,
                data: RowSpan { file, first_row: 0 },
                videos,
            });
            first += rows;
        }
        Ok(episodes)
    }

    /// v3.0: the data files the episode metadata names, in order, their rows cut into episodes by
    /// `episode_index`.
    fn concatenated(&self, columns: &mut [Vec<f64>]) -> Result<Vec<EpisodeRows>, DatasetError> {
        let names: Vec<String> = self.info.videos.iter().map(|v| v.name.clone()).collect();
        let listed = episodes::read_parquet(self.dir, &names, self.progress)?;
        let files: BTreeSet<(usize, usize)> = listed.iter().map(|l| l.data_file).collect();
        let mut runs = Runs::default();
        let mut first = 0;
        // Each file read and the table's row its first row became.
        let mut starts: Vec<(PathBuf, usize)> = Vec::new();
        for (chunk, file) in files {
            let file = self.data_file(&[("chunk_index", chunk), ("file_index", file)])?;
            let rows = append_file(&file, self.wanted, columns, self.progress)?;
            runs.add(&file, first, &columns[self.episode_column][first..])?;
            starts.push((file, first));
            first += rows;
        }
        let data_of = |rows: &Range<usize>| {
            let at = starts.partition_point(|(_, start)| *start <= rows.start);
            let (file, start) = (starts.get(at.saturating_sub(1)).cloned()).unwrap_or_default();
            RowSpan {
                file,
                first_row: rows.start - start,
            }
        };
        let by_index: HashMap<usize, &Listed> = listed.iter().map(|l| (l.index, l)).collect();
        let runs = runs.check(&listed, &self.dir.join(EPISODES_DIR))?;
        (runs.into_iter())
            .map(|(index, rows)| {
                // Every run's episode is listed: `check` makes sure.
                let located = by_index.get(&index).map_or(&[][..], |l| &l.videos[..]);
                let videos = (names.iter().zip(located))
                    .map(|(name, at)| {
                        let fields = [("chunk_index", at.file.0), ("file_index", at.file.1)];
                        let file = self.video_file(name, &fields)?;
                        Ok(VideoSpan {
                            file,
                            from_s: at.from_s,
                        })
                    })
                    .collect::<Result<_, DatasetError>>()?;
                let data = data_of(&rows);
                Ok(EpisodeRows { rows, data, videos })
            })
            .collect()
    }
}
