//! What can be wrong with an MIT Push Dataset file, beside the reader that finds it.

use crate::recording::resample::SpanProblem;

/// What is wrong with an MIT Push Dataset file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MitProblem {
    #[error(
        "file name is not an MIT Push Dataset name ({why}), expected motion_surface=<surface>_shape=<shape>_a=<mm/s²>_v=<mm/s>_i=<side>_s=<position>_t=<angle>"
    )]
    FileName { why: String },
    #[error(
        "unknown shape '{0}', expected one of rect1, rect2, rect3, tri1, tri2, tri3, ellip1, ellip2, ellip3, hex, butter"
    )]
    UnknownShape(String),
    #[error("not valid JSON for an MIT push: {0}")]
    Json(String),
    #[error("not a readable HDF5 file: {0}")]
    Hdf5(String),
    #[error("missing `{0}`, expected the three streams tip_pose, object_pose and ft_wrench")]
    MissingKey(&'static str),
    #[error("`{key}` has shape {shape}, expected N x 4 float64")]
    BadShape { key: &'static str, shape: String },
    #[error("`{key}` row {row} column {column} is {value}, expected a finite number")]
    NonFinite {
        key: &'static str,
        row: usize,
        column: usize,
        value: f64,
    },
    #[error("`{key}` row {row} column {column} is {value}, expected {expected}")]
    OutOfRange {
        key: &'static str,
        row: usize,
        column: usize,
        value: f64,
        expected: &'static str,
    },
    #[error("`{key}` has only {rows} usable rows, expected at least {min}")]
    TooFewRows {
        key: &'static str,
        rows: usize,
        min: usize,
    },
    /// The tip and object streams overlap too little, or span too long.
    #[error("the tip and object streams {0}")]
    Span(SpanProblem),
}
