//! What can be wrong with a ROS 2 bag, or with the topics asked of it, beside the reader that finds
//! it.

use std::path::PathBuf;

use super::topic_info::{BagListing, TF_STATIC, TopicInfo};
use crate::recording::resample::SpanProblem;

/// What is wrong with a ROS 2 bag, or with the topics asked of it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BagProblem {
    #[error("not a readable MCAP file: {0}")]
    Mcap(String),
    /// The load it was read for was cancelled.
    #[error("opening cancelled")]
    Cancelled,
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
        "topic `{topic}` carries {type_name} (encoding {encoding}), not camera frames; pushlab reads \
         sensor_msgs/msg/CompressedImage (jpeg, png) and sensor_msgs/msg/Image in CDR"
    )]
    NotACamera {
        topic: String,
        type_name: String,
        encoding: String,
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
        chain.join(" → "), static_topic = TF_STATIC
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
        /// From the child frame up to the root (boxed slices keep `BagError` small).
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
        topic_listing(&listing.topics)
    )]
    NeedsImport { listing: BagListing },
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
    /// The pusher and object streams overlap too little, or span too long (then a bag of several
    /// pushes can be split at its pauses).
    #[error("the pusher and object streams {}{}", .0, split_hint(.0))]
    Span(SpanProblem),
}

/// `"/a (type), /b (type, not readable)"`: a bag's topics as an error lists them.
fn topic_listing(topics: &[TopicInfo]) -> String {
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

impl BagProblem {
    /// The problem with the chunk's index filled in, for a problem found inside a chunk before its
    /// index was known.
    pub(crate) fn in_chunk(self, index: usize) -> Self {
        match self {
            BagProblem::Chunk { why, .. } => BagProblem::Chunk { index, why },
            other => other,
        }
    }
}

/// What to do about a span too long to be one push: split the bag at its pauses.
fn split_hint(span: &SpanProblem) -> &'static str {
    match span {
        SpanProblem::TooLong { .. } => "; split it with --split-gap",
        SpanProblem::TooShort { .. } => "",
    }
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
