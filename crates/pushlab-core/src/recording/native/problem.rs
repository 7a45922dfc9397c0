//! What can be wrong at one line of a native CSV file, beside the reader that finds it, with the one
//! header the reader, the writer and the messages name.

/// The only accepted CSV header, in this column order.
pub const CSV_HEADER: &str = "time,robot_x,robot_y,object_x,object_y,object_theta";

/// What is wrong at one line of a native CSV file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CsvProblem {
    #[error("the file is empty, expected the header `{expected}`", expected = CSV_HEADER)]
    Empty,
    #[error("the line is not valid UTF-8 text")]
    NotUtf8,
    #[error("header is '{found}', expected `{expected}`", expected = CSV_HEADER)]
    Header { found: String },
    #[error("{found} fields, expected 6 ({expected})", expected = CSV_HEADER)]
    FieldCount { found: usize },
    #[error("{column} is '{text}', expected a number")]
    NotANumber { column: &'static str, text: String },
    #[error("{column} is '{text}', expected a finite number")]
    NotFinite { column: &'static str, text: String },
    #[error("{column} is '{text}', expected a magnitude of at most {limit:e}")]
    OutOfRange {
        column: &'static str,
        text: String,
        limit: f64,
    },
    #[error(
        "time {time} is not after the previous row's {previous}, expected strictly increasing time"
    )]
    TimeNotIncreasing { time: f64, previous: f64 },
    #[error("only {rows} data rows, expected at least 2")]
    TooFewRows { rows: usize },
}
