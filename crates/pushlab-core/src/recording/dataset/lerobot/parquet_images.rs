//! The pictures of a LeRobot image feature (dtype `image`), read from the parquet files when shown:
//! each row's cell is the struct Hugging Face `datasets` writes, `{bytes, path}`, the bytes a PNG
//! or JPEG (`lerobot/pusht_image`). Opening a dataset reads none of them; a reader keeps the
//! pictures of one row group of its episode (the group of the frame asked for last), so memory is
//! bounded by a row group's pictures, not by the file (a v3.0 file holds many episodes).

use std::path::{Path, PathBuf};

use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;

use super::parquet_source::ParquetSource;
use crate::recording::camera::{EncodedImage, FrameProblem, FrameReader, FrameSource, sniff};

/// One episode's pictures of an image feature.
pub struct ParquetImages {
    file: PathBuf,
    column: String,
    /// The row of the episode's first frame in the file.
    first_row: usize,
    frames: usize,
}

impl ParquetImages {
    /// The `frames` pictures of `column` from row `first_row` of `file` on.
    pub fn new(file: PathBuf, column: String, first_row: usize, frames: usize) -> Self {
        Self {
            file,
            column,
            first_row,
            frames,
        }
    }
}

impl FrameSource for ParquetImages {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(Reader {
            file: self.file.clone(),
            column: self.column.clone(),
            first_row: self.first_row,
            frames: self.frames,
            group: None,
        })
    }

    fn location(&self) -> PathBuf {
        self.file.clone()
    }
}

/// The pictures of one row group, those of the episode: the file's rows `rows` start at `first`.
struct Group {
    first: usize,
    pictures: Vec<Result<Vec<u8>, String>>,
}

struct Reader {
    file: PathBuf,
    column: String,
    first_row: usize,
    frames: usize,
    group: Option<Group>,
}

impl FrameReader for Reader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        if index >= self.frames {
            return Err(FrameProblem::Unreadable(format!(
                "frame {index} is past the episode's {} frames",
                self.frames
            )));
        }
        let row = self.first_row + index;
        let held = |g: &Group| (g.first..g.first + g.pictures.len()).contains(&row);
        if !self.group.as_ref().is_some_and(held) {
            self.group = None;
            let wanted = self.first_row..self.first_row + self.frames;
            let group = read_group(&self.file, &self.column, row, wanted).map_err(|why| {
                FrameProblem::Unreadable(format!("{}: {why}", self.file.display()))
            })?;
            self.group = Some(group);
        }
        let picture = (self.group.as_ref())
            .and_then(|g| g.pictures.get(row - g.first))
            .ok_or_else(|| FrameProblem::Unreadable(format!("row {row} is not in the file")))?;
        let file = self.file.display();
        let bytes = (picture.clone())
            .map_err(|why| FrameProblem::Unreadable(format!("{file}: row {row}: {why}")))?;
        let format = sniff(&bytes).ok_or_else(|| {
            FrameProblem::Unreadable(format!(
                "{file}: row {row}'s `{}` holds {} bytes that are neither PNG nor JPEG",
                self.column,
                bytes.len()
            ))
        })?;
        Ok(EncodedImage { format, bytes })
    }
}

/// The pictures of `column` in the row group holding `row`, those of the rows `wanted`. The parquet
/// crate asserts some of what it decodes: a panic on a corrupt file is this frame's error.
fn read_group(
    file: &Path,
    column: &str,
    row: usize,
    wanted: std::ops::Range<usize>,
) -> Result<Group, String> {
    let read = std::panic::catch_unwind(|| read_group_unguarded(file, column, row, wanted));
    read.unwrap_or_else(|_| Err("the parquet reader stopped on corrupt data".to_owned()))
}

fn read_group_unguarded(
    file: &Path,
    column: &str,
    row: usize,
    wanted: std::ops::Range<usize>,
) -> Result<Group, String> {
    let source = ParquetSource::open(file).map_err(|e| e.to_string())?;
    let reader = SerializedFileReader::new(source).map_err(|e| e.to_string())?;
    let metadata = reader.metadata();
    let field = (metadata.file_metadata().schema().get_fields().iter())
        .find(|f| f.name() == column)
        .cloned()
        .ok_or_else(|| format!("no column `{column}`, expected the image feature's pictures"))?;
    let mut group_first = 0usize;
    for g in 0..metadata.num_row_groups() {
        let rows = usize::try_from(metadata.row_group(g).num_rows()).unwrap_or(0);
        if row >= group_first + rows {
            group_first += rows;
            continue;
        }
        let projection = parquet::schema::types::Type::group_type_builder("schema")
            .with_fields(vec![field])
            .build()
            .map_err(|e| e.to_string())?;
        let first = wanted.start.max(group_first);
        let last = wanted.end.min(group_first + rows);
        let group = reader.get_row_group(g).map_err(|e| e.to_string())?;
        let rows_read = group
            .get_row_iter(Some(projection))
            .map_err(|e| e.to_string())?;
        let mut pictures = Vec::with_capacity(last.saturating_sub(first));
        for (k, read) in rows_read.enumerate().skip(first - group_first) {
            if group_first + k >= last {
                break;
            }
            let read = read.map_err(|e| e.to_string())?;
            pictures.push(picture(
                read.get_column_iter().next().map(|(_, f)| f),
                column,
            ));
        }
        return Ok(Group { first, pictures });
    }
    Err(format!("row {row} is past the file's {group_first} rows"))
}

/// The picture in one cell: the struct's `bytes`; why not, in words.
fn picture(cell: Option<&Field>, column: &str) -> Result<Vec<u8>, String> {
    let Some(Field::Group(cell)) = cell else {
        return Err(format!(
            "`{column}` is not the struct of bytes and path an image feature is stored as"
        ));
    };
    let field = |name: &str| {
        cell.get_column_iter()
            .find(|(n, _)| n.as_str() == name)
            .map(|(_, f)| f)
    };
    match (field("bytes"), field("path")) {
        (Some(Field::Bytes(bytes)), _) => Ok(bytes.data().to_vec()),
        (_, Some(Field::Str(path))) => Err(format!(
            "its picture is a file path ({path}), not bytes in the parquet file: not read"
        )),
        _ => Err(format!("`{column}.bytes` is empty")),
    }
}
