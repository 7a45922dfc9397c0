//! What can go wrong reading or writing recordings.
//!
//! Every error names the file it is about and, where it can, the line or field and what was expected,
//! so that a user can open the file and fix it without reading pushlab's code.

use std::path::{Path, PathBuf};

/// Why a recording (or a whole set) could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file or folder could not be read at all.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A native CSV file is malformed at a given line (1-based, the header is line 1).
    #[error("{} line {line}: {problem}", path.display())]
    Csv {
        path: PathBuf,
        line: usize,
        problem: CsvProblem,
    },
    /// `setting.json` is not valid JSON or does not match the schema.
    #[error("{}: {message}", path.display())]
    SettingJson { path: PathBuf, message: String },
    /// `setting.json` parses but a field has an unusable value.
    #[error("{}: field `{field}`: {problem}", path.display())]
    SettingField {
        path: PathBuf,
        field: String,
        problem: String,
    },
    /// `setting.json` lists a trajectory whose CSV is not in the folder.
    #[error("{}: listed in setting.json but the file does not exist", path.display())]
    MissingTrajectory { path: PathBuf },
    /// A CSV passed on its own has no `setting.json` beside it.
    #[error("{}: no setting.json in the same folder, expected a native recording set", path.display())]
    NoSetting { path: PathBuf },
    /// An MIT Push Dataset file that cannot be used.
    #[error("{}: {problem}", path.display())]
    Mit { path: PathBuf, problem: MitProblem },
    /// A ROS 2 bag (an `.mcap` file or a rosbag2 folder) that cannot be used; `path` is the `.mcap`
    /// file the problem is in, or the folder.
    #[error("{}: {problem}", path.display())]
    Bag { path: PathBuf, problem: BagProblem },
    /// A path that is none of the things pushlab can open.
    #[error(
        "{}: not a recording: expected a native set folder (with setting.json), a folder of sets, a CSV inside a set, or an MIT Push Dataset .json/.h5 file",
        path.display()
    )]
    NotRecognised { path: PathBuf },
    /// A file too large for the memory that is free (see `MEMORY_PER_FILE_BYTE`).
    #[error(
        "{}: too large to open: the file is {} and opening it needs about {} of memory, but {} \
         free; split the recording into shorter files or free memory",
        path.display(),
        gigabytes(*bytes),
        gigabytes(bytes.saturating_mul(super::read::MEMORY_PER_FILE_BYTE)),
        available.map_or("less is".to_owned(), |a| format!("{} are", gigabytes(a)))
    )]
    TooLarge {
        path: PathBuf,
        bytes: u64,
        /// Free memory when it was checked, bytes.
        available: Option<u64>,
    },
    /// A folder in which no recording was found.
    #[error("{}: no recordings found (no setting.json and no MIT Push Dataset files inside)", path.display())]
    NothingFound { path: PathBuf },
}

impl LoadError {
    /// The file or folder the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::Io { path, .. }
            | LoadError::Csv { path, .. }
            | LoadError::SettingJson { path, .. }
            | LoadError::SettingField { path, .. }
            | LoadError::MissingTrajectory { path }
            | LoadError::NoSetting { path }
            | LoadError::Mit { path, .. }
            | LoadError::Bag { path, .. }
            | LoadError::NotRecognised { path }
            | LoadError::TooLarge { path, .. }
            | LoadError::NothingFound { path } => path,
        }
    }

    /// Whether the file or folder does not exist (it vanished, or was never there).
    pub fn is_not_found(&self) -> bool {
        matches!(self, LoadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound)
    }

    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        LoadError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Bytes as gigabytes with one decimal (10⁹ bytes, as file managers show them).
fn gigabytes(bytes: u64) -> String {
    format!("{:.1} GB", bytes as f64 / 1e9)
}

/// What is wrong at one line of a native CSV file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CsvProblem {
    #[error("the file is empty, expected the header `{expected}`", expected = crate::recording::native::CSV_HEADER)]
    Empty,
    #[error("the line is not valid UTF-8 text")]
    NotUtf8,
    #[error("header is '{found}', expected `{expected}`", expected = crate::recording::native::CSV_HEADER)]
    Header { found: String },
    #[error("{found} fields, expected 6 ({expected})", expected = crate::recording::native::CSV_HEADER)]
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
    #[error("the streams span {seconds:.0} s, expected a push shorter than {max} s (broken timestamps?)", max = crate::recording::mit_push::MAX_DURATION_S)]
    TooLong { seconds: f64 },
    #[error(
        "the tip and object streams overlap for only {seconds:.3} s, expected at least {min} s"
    )]
    TooShort { seconds: f64, min: f64 },
}

/// What is wrong with a ROS 2 bag, or with the topics asked of it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BagProblem {
    #[error("not a readable MCAP file: {0}")]
    Mcap(String),
    #[error("chunk {index} (counting from 0): {why}")]
    Chunk { index: usize, why: String },
    #[error(
        "a rosbag2 folder, but it holds no .mcap file (expected the files metadata.yaml lists)"
    )]
    NoMcapFiles,
    #[error("no topic `{topic}` in the bag; its topics: {available}")]
    MissingTopic { topic: String, available: String },
    #[error(
        "topic `{topic}` carries {type_name} (encoding {encoding}), which pushlab cannot read; it reads \
         geometry_msgs/msg/PoseStamped, tf2_msgs/msg/TFMessage, nav_msgs/msg/Odometry and \
         geometry_msgs/msg/Pose2D in CDR; the bag's topics: {available}"
    )]
    UnsupportedType {
        topic: String,
        type_name: String,
        encoding: String,
        available: String,
    },
    #[error(
        "topic `{topic}` is a tf2_msgs/msg/TFMessage: name the child frame, as `{topic}:FRAME`{}",
        seen_frames(seen)
    )]
    NeedChildFrame { topic: String, seen: Vec<String> },
    #[error(
        "topic `{topic}` has no transform with child frame `{frame}`{}",
        seen_frames(seen)
    )]
    NoChildFrame {
        topic: String,
        frame: String,
        seen: Vec<String>,
    },
    #[error(
        "topic `{topic}` message {index}: frame `{frame}` has two parents, `{}`; expected one tree \
         (each frame published under one parent)",
        parents.join("` and `")
    )]
    TwoParents {
        topic: String,
        frame: String,
        /// The first parent seen, then the other.
        parents: Vec<String>,
        /// The message (0-based on its topic, in its file) that gave the second parent.
        index: u64,
    },
    #[error(
        "the transforms of `{topic}` and {static_topic} form a loop: {}; expected a tree",
        chain.join(" → "), static_topic = crate::recording::bag::TF_STATIC
    )]
    FrameLoop {
        topic: String,
        /// The frames from the one asked for, up its parents, back to one already on the way.
        chain: Vec<String>,
    },
    #[error(
        "pusher `{pusher}`'s chain ({}) ends in `{}`, object `{object}`'s ({}) in `{}`; expected \
         both in one fixed frame",
        pusher_chain.join(" → "), last(pusher_chain), object_chain.join(" → "), last(object_chain)
    )]
    DifferentRoots {
        pusher: String,
        /// From the child frame up to the root (boxed slices keep `LoadError` small).
        pusher_chain: Box<[String]>,
        object: String,
        object_chain: Box<[String]>,
    },
    #[error(
        "`{spec}`: every transform of its chain ({}) is static, so it has no times to be read at; \
         expected the frame, or a frame above it, published on `{topic}`",
        chain.join(" → ")
    )]
    StaticChain {
        spec: String,
        topic: String,
        chain: Vec<String>,
    },
    #[error("topic `{topic}` message {index} ({type_name}): cannot decode: {why}")]
    Decode {
        topic: String,
        /// 0-based among the topic's messages, in file order.
        index: u64,
        type_name: &'static str,
        why: String,
    },
    #[error(
        "a ROS 2 bag whose pusher and object topics are not chosen yet: open it in the app to choose \
         them (remembered beside the bag), or import it into a recording set (`pushlab import BAG \
         --pusher TOPIC --object TOPIC --setting SETTING.json --out SET`); its topics: {}",
        topic_listing(topics)
    )]
    NeedsImport { topics: Vec<super::bag::TopicInfo> },
    #[error("not a pushlab bag choice: {why}")]
    BadChoice { why: String },
    #[error(
        "the topics remembered in {} do not fit the bag: {why}; choose them again (in the app: \
         its Choose topics… button under the load problems) or delete that file",
        choice_file.display()
    )]
    ChoiceFailed { choice_file: PathBuf, why: String },
    #[error("topic `{topic}` message {index}: {why}")]
    BadValue {
        topic: String,
        index: u64,
        why: String,
    },
    #[error("`{topic}` has only {rows} usable messages, expected at least {min}")]
    TooFewRows {
        topic: String,
        rows: usize,
        min: usize,
    },
    #[error("the pusher and object streams span {seconds:.0} s, expected a push shorter than {max} s (broken timestamps?); split it with --split-gap", max = crate::recording::mit_push::MAX_DURATION_S)]
    TooLong { seconds: f64 },
    #[error(
        "the pusher and object streams overlap for only {seconds:.3} s, expected at least {min} s"
    )]
    TooShort { seconds: f64, min: f64 },
}

/// `"/a (type), /b (type, not readable)"`: a bag's topics as an error lists them.
fn topic_listing(topics: &[super::bag::TopicInfo]) -> String {
    if topics.is_empty() {
        return "none".to_owned();
    }
    topics
        .iter()
        .map(|t| {
            let readable = if t.pose_type().is_some() {
                ""
            } else {
                ", not readable"
            };
            format!("{} ({}{readable})", t.topic, t.type_name)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn last(chain: &[String]) -> &str {
    chain.last().map_or("", String::as_str)
}

fn seen_frames(seen: &[String]) -> String {
    if seen.is_empty() {
        "; it carries no transforms".to_owned()
    } else {
        format!("; child frames seen: {}", seen.join(", "))
    }
}

/// Why a recording set could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("{}: cannot write: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("setting.json lists {entries} trajectories but {trajectories} were given")]
    CountMismatch { entries: usize, trajectories: usize },
    #[error("trajectory file name '{0}' must be a plain file name ending in .csv (no folders)")]
    BadFileName(String),
    #[error("trajectory '{file}' frame {frame}: {problem}")]
    BadTrajectory {
        file: String,
        frame: usize,
        problem: String,
    },
    #[error("cannot serialise setting.json: {0}")]
    Json(String),
}
