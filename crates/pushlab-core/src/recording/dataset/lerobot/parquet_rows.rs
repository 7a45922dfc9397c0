//! The numeric columns of one parquet file, row by row through the parquet crate's record API (no
//! arrow): only the columns asked for are decoded (a v2 dataset's images, stored in the parquet
//! files, are never touched), every cell checked to hold the number of values asked, scalars and
//! (nested) lists alike. A null reads as NaN, refused by the import where it is used.

use std::collections::HashMap;
use std::path::Path;

use parquet::errors::ParquetError;
use parquet::file::reader::{FileReader, Length as _, SerializedFileReader};
use parquet::record::Field;
use parquet::schema::types::Type;

use super::super::error::DatasetError;
use super::super::problem::DatasetProblem;
use super::parquet_source::ParquetSource;
use crate::recording::progress::Progress;

/// Rows between two looks at the cancel flag, within a row group.
const ROWS_PER_CANCEL_CHECK: usize = 4096;

/// A column to read: its name, the values each cell holds, and what they should be, for messages.
#[derive(Clone, Debug)]
pub struct Wanted {
    pub name: String,
    pub width: usize,
    /// `2 float32 value(s) (shape [2] in meta/info.json)`.
    pub expected: String,
    /// Who wants it, for a missing column: `meta/info.json lists as a feature`.
    pub wanted_by: String,
}

/// Appends the cells of `path`'s columns `wanted` to `into` (one vector per column, `width` values
/// a row); returns the rows read. `progress` is told each row group's bytes and stops the read
/// between row groups and every few thousand rows.
///
/// The parquet crate asserts some of what it decodes (a corrupt run-length header panics in its bit
/// reader: found by garbling the fixture byte by byte); such a panic is caught and becomes this
/// file's error, so that a corrupt file never takes the app down.
pub fn append_file(
    path: &Path,
    wanted: &[Wanted],
    into: &mut [Vec<f64>],
    progress: &dyn Progress,
) -> Result<usize, DatasetError> {
    let read = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        read_columns(path, wanted, into, progress)
    }));
    read.unwrap_or_else(|panic| {
        let why = (panic.downcast_ref::<String>().map(String::as_str))
            .or_else(|| panic.downcast_ref::<&str>().copied())
            .unwrap_or("corrupt data");
        Err(DatasetError::Problem {
            path: path.to_path_buf(),
            problem: DatasetProblem::Parquet(format!("the reader stopped: {why}")),
        })
    })
}

fn read_columns(
    path: &Path,
    wanted: &[Wanted],
    into: &mut [Vec<f64>],
    progress: &dyn Progress,
) -> Result<usize, DatasetError> {
    let fail = |problem| DatasetError::Problem {
        path: path.to_path_buf(),
        problem,
    };
    let parquet = |e: ParquetError| fail(DatasetProblem::Parquet(e.to_string()));
    let cancelled = || fail(DatasetProblem::Cancelled);
    let file = ParquetSource::open(path).map_err(|e| DatasetError::io(path, e))?;
    let size = file.len();
    let reader = SerializedFileReader::new(file).map_err(parquet)?;
    let schema = reader.metadata().file_metadata().schema();
    let fields = schema.get_fields();
    let mut projected = Vec::with_capacity(wanted.len());
    for column in wanted {
        match fields.iter().find(|f| f.name() == column.name) {
            Some(field) => projected.push(field.clone()),
            None => {
                let names: Vec<&str> = fields.iter().map(|f| f.name()).collect();
                return Err(fail(DatasetProblem::MissingColumn {
                    name: column.name.clone(),
                    wanted_by: column.wanted_by.clone(),
                    columns: names.join(", "),
                }));
            }
        }
    }
    let projection = Type::group_type_builder(schema.name())
        .with_fields(projected)
        .build()
        .map_err(parquet)?;
    let index: HashMap<&str, usize> = (wanted.iter().enumerate())
        .map(|(i, c)| (c.name.as_str(), i))
        .collect();
    let mut rows = 0usize;
    let mut passed = 0u64;
    for group in 0..reader.num_row_groups() {
        if progress.is_cancelled() {
            return Err(cancelled());
        }
        let group = reader.get_row_group(group).map_err(parquet)?;
        let group_bytes = u64::try_from(group.metadata().compressed_size()).unwrap_or(0);
        for row in group
            .get_row_iter(Some(projection.clone()))
            .map_err(parquet)?
        {
            let row = row.map_err(parquet)?;
            for (name, field) in row.get_column_iter() {
                let Some(&i) = index.get(name.as_str()) else {
                    continue;
                };
                let column = &wanted[i];
                let values = &mut into[i];
                let before = values.len();
                let bad = |found: String| {
                    fail(DatasetProblem::Column {
                        column: column.name.clone(),
                        row: rows,
                        found,
                        expected: column.expected.clone(),
                    })
                };
                if matches!(field, Field::Null) {
                    values.resize(before + column.width, f64::NAN);
                    continue;
                }
                push_values(field, values).map_err(bad)?;
                let count = values.len() - before;
                if count != column.width {
                    return Err(bad(format!("{count} value(s)")));
                }
            }
            rows += 1;
            if rows.is_multiple_of(ROWS_PER_CANCEL_CHECK) && progress.is_cancelled() {
                return Err(cancelled());
            }
        }
        progress.advance(group_bytes);
        passed += group_bytes;
    }
    progress.advance(size.saturating_sub(passed));
    Ok(rows)
}

/// Appends a cell's numbers, lists flattened in order; a value that is not a number is `Err`
/// saying what it is.
fn push_values(field: &Field, out: &mut Vec<f64>) -> Result<(), String> {
    let value = match field {
        Field::Null => f64::NAN,
        Field::Byte(v) => f64::from(*v),
        Field::Short(v) => f64::from(*v),
        Field::Int(v) => f64::from(*v),
        Field::Long(v) => *v as f64,
        Field::UByte(v) => f64::from(*v),
        Field::UShort(v) => f64::from(*v),
        Field::UInt(v) => f64::from(*v),
        Field::ULong(v) => *v as f64,
        Field::Float16(v) => f64::from(*v),
        Field::Float(v) => f64::from(*v),
        Field::Double(v) => *v,
        Field::ListInternal(list) => {
            for element in list.elements() {
                push_values(element, out)?;
            }
            return Ok(());
        }
        Field::Bool(v) => return Err(format!("a boolean ({v})")),
        Field::Str(v) => {
            return Err(format!(
                "text \"{}\"",
                v.chars().take(40).collect::<String>()
            ));
        }
        Field::Bytes(v) => return Err(format!("{} bytes", v.len())),
        Field::Group(_) => return Err("a struct".into()),
        Field::MapInternal(_) => return Err("a map".into()),
        other => return Err(format!("a {} value", kind(other))),
    };
    out.push(value);
    Ok(())
}

/// The name of a parquet value's kind that is none of the above (dates, decimals, times).
fn kind(field: &Field) -> &'static str {
    match field {
        Field::Decimal(_) => "decimal",
        Field::Date(_) => "date",
        Field::TimeMillis(_) | Field::TimeMicros(_) => "time",
        Field::TimestampMillis(_) | Field::TimestampMicros(_) => "timestamp",
        _ => "non-numeric",
    }
}
