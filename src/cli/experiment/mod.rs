//! `pushlab train` and `pushlab eval`: the paper's experiments from the command line, on any
//! recordings the importer reads, with the same core code the app uses.
//!
//! Which recordings, samples and models an experiment uses, and how they are trained and evaluated,
//! is `pushlab_core::experiment`; these modules parse the command line and present the results:
//! - [`data`]: the summary of the recordings used;
//! - [`train_progress`]: offline training's per-epoch progress bar and the Ctrl-C cancel flag;
//! - [`train`]: the `train` command;
//! - [`eval`]: the `eval` command, its table and its JSON report;
//! - [`suite`]: the `suite` command, many experiments in parallel into one table;
//! - [`plot`]: the paper-style figure.
//!
//! Exit codes: 0 done, 1 nothing usable / a file could not be written, 2 wrong arguments.

pub mod args;
pub mod data;
pub mod eval;
pub mod suite;
pub mod suite_tables;
pub mod train;
pub mod train_progress;
