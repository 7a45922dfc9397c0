//! Which episodes a LeRobot dataset holds, and where their rows are: v2.x lists them in
//! `meta/episodes.jsonl` (index and length; one parquet file each), v3.0 in the parquet files of
//! `meta/episodes/` (index, length and the data file they are in). The data's own `episode_index`
//! column says which rows are whose; [`Runs`] checks that each episode's rows come one after the
//! other and that they agree with the metadata.

use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use super::super::error::DatasetError;
use super::super::problem::DatasetProblem;
use super::parquet_rows::{Wanted, append_file};
use crate::json_problem::JsonProblem;
use crate::recording::progress::Progress;
use crate::recording::read::read_file;

/// v2.x's episode list, relative to the dataset's folder.
pub const EPISODES_JSONL: &str = "meta/episodes.jsonl";
/// v3.0's folder of episode metadata parquet files.
pub const EPISODES_DIR: &str = "meta/episodes";

/// An episode as the metadata lists it.
#[derive(Clone, Debug, PartialEq)]
pub struct Listed {
    /// `episode_index`.
    pub index: usize,
    /// Its frames.
    pub length: usize,
    /// v3.0: the data file it is in, (`data/chunk_index`, `data/file_index`).
    pub data_file: (usize, usize),
    /// v3.0: where its frames of each video feature are, in the order asked for.
    pub videos: Vec<VideoLocation>,
}

/// v3.0: where an episode's frames of one video feature are: the file
/// (`videos/KEY/chunk_index`, `videos/KEY/file_index`) and the time in it of the episode's first
/// frame (`videos/KEY/from_timestamp`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VideoLocation {
    pub file: (usize, usize),
    pub from_s: f64,
}

/// `meta/episodes.jsonl`: one JSON object a line, with `episode_index` and `length`; sorted by
/// index.
pub fn read_jsonl(dir: &Path) -> Result<Vec<Listed>, DatasetError> {
    let path = dir.join(EPISODES_JSONL);
    let bytes = read_file(&path)?;
    let fail = |problem| DatasetError::Problem {
        path: path.clone(),
        problem,
    };
    let mut listed = Vec::new();
    for (i, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let value: serde_json::Value = serde_json::from_slice(line).map_err(|e| {
            let mut problem = JsonProblem::of(&e);
            problem.line = i + 1;
            fail(DatasetProblem::Json(problem))
        })?;
        let whole = |key: &str| {
            value
                .get(key)
                .and_then(serde_json::Value::as_u64)
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| {
                    fail(DatasetProblem::Field {
                        field: format!("line {}: {key}", i + 1),
                        why: format!(
                            "{}, expected a whole number",
                            value.get(key).unwrap_or(&serde_json::Value::Null)
                        ),
                    })
                })
        };
        listed.push(Listed {
            index: whole("episode_index")?,
            length: whole("length")?,
            data_file: (0, 0),
            videos: Vec::new(),
        });
    }
    sorted(listed).map_err(fail)
}

/// v3.0's episode metadata: every parquet file under `meta/episodes/`, in name order; sorted by
/// index. With the location of each episode's frames in each of `videos` (video feature names).
pub fn read_parquet(
    dir: &Path,
    videos: &[String],
    progress: &dyn Progress,
) -> Result<Vec<Listed>, DatasetError> {
    let files = parquet_files(&dir.join(EPISODES_DIR));
    if files.is_empty() {
        return Err(DatasetError::Problem {
            path: dir.join(EPISODES_DIR),
            problem: DatasetProblem::Episodes(
                "no parquet file, expected LeRobot v3.0's episode metadata \
                 (chunk-000/file-000.parquet)"
                    .into(),
            ),
        });
    }
    let mut names: Vec<String> = [
        "episode_index",
        "length",
        "data/chunk_index",
        "data/file_index",
    ]
    .map(String::from)
    .to_vec();
    for video in videos {
        for column in ["chunk_index", "file_index", "from_timestamp"] {
            names.push(format!("videos/{video}/{column}"));
        }
    }
    let wanted: Vec<Wanted> = (names.iter())
        .map(|name| Wanted {
            name: name.clone(),
            width: 1,
            expected: if name.ends_with("timestamp") {
                "seconds".into()
            } else {
                "a whole number".into()
            },
            wanted_by: "every LeRobot v3.0 episode metadata file has".into(),
        })
        .collect();
    let mut listed = Vec::new();
    for file in &files {
        let mut columns = vec![Vec::new(); names.len()];
        append_file(file, &wanted, &mut columns, progress)?;
        let rows = columns.first().map_or(0, Vec::len);
        for row in 0..rows {
            // Every column holds one value a row: this row's cells, column by column.
            let cells: Vec<f64> = columns.iter().map(|column| column[row]).collect();
            let bad = |column: usize, expected: &str| DatasetError::Problem {
                path: file.clone(),
                problem: DatasetProblem::Column {
                    column: names[column].clone(),
                    row,
                    found: cells[column].to_string(),
                    expected: expected.into(),
                },
            };
            let whole = |column: usize| {
                whole_number(cells[column]).ok_or_else(|| bad(column, "a whole number"))
            };
            let seconds = |column: usize| {
                let value = cells[column];
                (value.is_finite() && value >= 0.0)
                    .then_some(value)
                    .ok_or_else(|| bad(column, "seconds, at least 0"))
            };
            let videos = (0..videos.len())
                .map(|k| {
                    let at = 4 + 3 * k;
                    Ok(VideoLocation {
                        file: (whole(at)?, whole(at + 1)?),
                        from_s: seconds(at + 2)?,
                    })
                })
                .collect::<Result<_, DatasetError>>()?;
            listed.push(Listed {
                index: whole(0)?,
                length: whole(1)?,
                data_file: (whole(2)?, whole(3)?),
                videos,
            });
        }
    }
    sorted(listed).map_err(|problem| DatasetError::Problem {
        path: dir.join(EPISODES_DIR),
        problem,
    })
}

fn sorted(mut listed: Vec<Listed>) -> Result<Vec<Listed>, DatasetProblem> {
    listed.sort_by_key(|l| l.index);
    match listed.windows(2).find(|w| w[0].index == w[1].index) {
        Some(w) => Err(DatasetProblem::Episodes(format!(
            "episode_index {} is listed twice",
            w[0].index
        ))),
        None => Ok(listed),
    }
}

/// A value that is a whole number a `usize` holds.
pub fn whole_number(value: f64) -> Option<usize> {
    (value.fract() == 0.0 && (0.0..9e15).contains(&value)).then_some(value as usize)
}

/// The `.parquet` files under `dir`, any depth, in path order.
pub fn parquet_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![dir.to_path_buf()];
    while let Some(folder) = folders.pop() {
        let Ok(entries) = crate::files::read_dir(&folder) else {
            continue;
        };
        for entry in entries {
            let path = entry.path;
            if entry.is_dir {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "parquet") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The episodes' rows, from the `episode_index` column of the data files read one after the other.
#[derive(Debug, Default)]
pub struct Runs {
    /// (episode index, the table's rows), in the order read.
    runs: Vec<(usize, Range<usize>)>,
    /// Where each episode's rows ended: the file and the file's row.
    ended: HashMap<usize, (PathBuf, usize)>,
}

impl Runs {
    /// Adds the `episode_index` values of `file`'s rows, which are the table's rows from `first`.
    pub fn add(&mut self, file: &Path, first: usize, indexes: &[f64]) -> Result<(), DatasetError> {
        let fail = |problem| DatasetError::Problem {
            path: file.to_path_buf(),
            problem,
        };
        for (row, &value) in indexes.iter().enumerate() {
            let index = whole_number(value).ok_or_else(|| {
                fail(DatasetProblem::Column {
                    column: "episode_index".into(),
                    row,
                    found: value.to_string(),
                    expected: "a whole number".into(),
                })
            })?;
            match self.runs.last_mut() {
                Some((last, rows)) if *last == index => rows.end = first + row + 1,
                _ => {
                    if let Some((earlier, end)) = self.ended.get(&index) {
                        return Err(fail(DatasetProblem::Episodes(format!(
                            "episode_index {index} at row {row} (counting from 0), but episode \
                             {index}'s rows ended at row {end} of {}; expected each episode's \
                             rows one after the other",
                            earlier.display()
                        ))));
                    }
                    self.runs.push((index, first + row..first + row + 1));
                }
            }
            self.ended.insert(index, (file.to_path_buf(), row));
        }
        Ok(())
    }

    /// The episodes' indexes and rows in the order read, each checked against the metadata's
    /// length; every episode listed must have rows. `meta` names the metadata, for errors.
    pub fn check(
        self,
        listed: &[Listed],
        meta: &Path,
    ) -> Result<Vec<(usize, Range<usize>)>, DatasetError> {
        let fail = |path: &Path, problem| DatasetError::Problem {
            path: path.to_path_buf(),
            problem,
        };
        let lengths: HashMap<usize, usize> = listed.iter().map(|l| (l.index, l.length)).collect();
        for (index, rows) in &self.runs {
            let (file, _) = &self.ended[index];
            match lengths.get(index) {
                None => {
                    return Err(fail(
                        file,
                        DatasetProblem::Episodes(format!(
                            "rows of episode {index}, which {} does not list",
                            meta.display()
                        )),
                    ));
                }
                Some(&length) if length != rows.len() => {
                    return Err(fail(
                        file,
                        DatasetProblem::Episodes(format!(
                            "episode {index} has {} rows, but {} says its length is {length}",
                            rows.len(),
                            meta.display()
                        )),
                    ));
                }
                Some(_) => {}
            }
        }
        if let Some(missing) = listed.iter().find(|l| !self.ended.contains_key(&l.index)) {
            return Err(fail(
                meta,
                DatasetProblem::Episodes(format!(
                    "episode {} is listed, but no data file has its rows",
                    missing.index
                )),
            ));
        }
        Ok(self.runs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_episode_whose_rows_come_back_later_is_refused() {
        let listed = [0, 1].map(|index| Listed {
            index,
            length: 2,
            data_file: (0, 0),
            videos: Vec::new(),
        });
        let mut runs = Runs::default();
        runs.add(Path::new("a.parquet"), 0, &[0.0, 0.0, 1.0])
            .expect("ok");
        runs.add(Path::new("b.parquet"), 3, &[1.0])
            .expect("continues");
        let rows = runs.check(&listed, Path::new("meta")).expect("agrees");
        assert_eq!(rows, vec![(0, 0..2), (1, 2..4)]);

        let mut runs = Runs::default();
        runs.add(Path::new("a.parquet"), 0, &[0.0, 1.0])
            .expect("ok");
        let error = runs
            .add(Path::new("b.parquet"), 2, &[1.0, 0.0])
            .expect_err("0 again");
        assert_eq!(
            error.to_string(),
            "b.parquet: episode_index 0 at row 1 (counting from 0), but episode 0's rows ended \
             at row 0 of a.parquet; expected each episode's rows one after the other"
        );
    }
}
