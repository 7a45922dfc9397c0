//! Import of ROS 2 bags: `.mcap` files and rosbag2 folders (a `metadata.yaml` beside `.mcap` files),
//! as `ros2 bag record` writes them since ROS 2 Iron.
//!
//! A bag holds many topics; the pusher and the object are two of them, named by the user (a topic,
//! and for `/tf` the child frame). Each message gives a planar pose: its header stamp (the log time
//! where the stamp is zero or the type has none), x, y and the yaw of its quaternion. The two
//! streams then go through the same cleaning and resampling as MIT Push Dataset files
//! ([`super::resample`]): stamps that do not increase are dropped and reported, gaps are reported,
//! and both are interpolated onto one grid over the interval both cover.
//!
//! Single-pose topics are taken as published: both streams must be in the same fixed frame. A
//! `/tf` frame is resolved through its transform tree ([`tf_tree`]): its pose in the root of its
//! chain of parents, composed from the topic's transforms and `/tf_static`'s; the pusher's and the
//! object's chains must end in the same root.

//! The reader's parts, each one concern: which files make a bag ([`files`]), the MCAP records and
//! chunks (`mcap_file`), the CDR messages (`cdr`), the topics and their listing (`topic_info`,
//! `topics`), transform trees (`tf_tree`), reading two pose streams (`streams`), putting them on one
//! grid and splitting at pauses (`split`), the user's choice remembered beside a bag ([`choice`])
//! and a bag opened as a recording set (`as_set`); what can go wrong is [`BagProblem`].

mod as_set;
mod camera;
mod cdr;
pub mod choice;
mod error;
mod files;
mod image_msg;
pub mod json_pose;
mod mcap;
mod message;
mod problem;
mod proto_pose;
mod spec;
mod split;
mod streams;
mod tf_tree;
mod topic_info;
mod topics;

pub use self::as_set::{open, open_with, setting_for};
pub use self::cdr::{
    PlanarPose, PoseType, Transform, decode_tf, encode_pose_stamped, encode_tf_message, yaw_of,
};
pub use self::choice::{BagChoice, SettingSource};
pub use self::error::BagError;
pub use self::files::{bag_files, is_bag};
pub use self::image_msg::{
    ImageKind, decode as decode_image_message, describe as describe_image_message,
    encode_compressed_image,
};
pub use self::message::decode as decode_pose;
pub use self::problem::BagProblem;
pub use self::spec::TopicSpec;
pub use self::split::{
    BagImport, BagPush, ImportOptions, MAX_RATE_HZ, import, import_bytes,
    import_bytes_with_cameras, import_with_cameras, resample_streams,
};
pub use self::streams::{BagStreams, FileCut, read_streams, read_streams_bytes};
pub(crate) use self::streams::{check_pose, seconds_since};
pub(crate) use self::tf_tree::{interpolate, isometry_of};
pub use self::topic_info::{BagListing, CameraInfo, MAX_LISTED_FRAMES, TF_STATIC, TopicInfo};
pub use self::topics::{topics, topics_bytes};
