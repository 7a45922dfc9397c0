//! What a bag's topic is, as pushlab lists it, and the topic names pushlab knows. A leaf of the bag
//! reader: the listing fills it, problems and choices name it.

use super::cdr::{self, PoseType};
use super::image_msg::ImageKind;

/// The topic whose transforms hold for all times (`tf2_ros::StaticTransformBroadcaster`'s).
pub const TF_STATIC: &str = "/tf_static";

/// One topic of a bag, for listing.
#[derive(Clone, Debug, PartialEq)]
pub struct TopicInfo {
    pub topic: String,
    /// The message type (the schema name), e.g. `geometry_msgs/msg/PoseStamped`.
    pub type_name: String,
    pub encoding: String,
    pub count: u64,
    /// First and last log time, nanoseconds.
    pub first_ns: u64,
    pub last_ns: u64,
    /// For a `tf2_msgs/msg/TFMessage` topic, the child frames its transforms carry, in order of
    /// first appearance (at most [`MAX_LISTED_FRAMES`]): what `TOPIC:CHILD_FRAME` can name.
    pub child_frames: Vec<String>,
    /// For a camera topic, what its first frame says of its frames.
    pub camera: Option<CameraInfo>,
}

/// What a camera topic's first frame says: its encoding (a CompressedImage's format string, an
/// Image's pixel encoding) and its size, when the first bytes tell it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CameraInfo {
    pub encoding: String,
    pub size: Option<(u32, u32)>,
}

/// Most child frames listed per TF topic: a tree of a few robots; more is listed as this many.
pub const MAX_LISTED_FRAMES: usize = 64;

impl TopicInfo {
    /// Whether its messages are camera frames pushlab reads.
    pub fn is_camera(&self) -> bool {
        self.encoding == "cdr" && ImageKind::from_schema(&self.type_name).is_some()
    }

    /// Lists a child frame, once, up to [`MAX_LISTED_FRAMES`].
    pub(crate) fn add_frame(&mut self, frame: &str) {
        if self.child_frames.len() < MAX_LISTED_FRAMES
            && !self.child_frames.iter().any(|f| f == frame)
        {
            self.child_frames.push(frame.to_owned());
        }
    }

    /// Messages per second of log time (0 for fewer than two messages).
    pub fn rate_hz(&self) -> f64 {
        let span = self.last_ns.saturating_sub(self.first_ns) as f64 * 1e-9;
        if self.count < 2 || span <= 0.0 {
            0.0
        } else {
            (self.count - 1) as f64 / span
        }
    }

    /// Notes the child frames of a TF message for listing. A message that does not decode is left
    /// to the import, which names it; listing still lists the topic.
    pub(super) fn note_frames(&mut self, payload: &[u8]) {
        if self.pose_type() != Some(PoseType::TfMessage) {
            return;
        }
        let frames = &mut self.child_frames;
        let _ = cdr::decode_tf(payload, |transform| {
            let child = transform.child;
            if frames.len() < MAX_LISTED_FRAMES && !frames.iter().any(|f| f.as_bytes() == child) {
                frames.push(String::from_utf8_lossy(child).into_owned());
            }
        });
    }

    /// The type pushlab reads it as, when it can (CDR-encoded and a known type, or a JSON pose).
    pub fn pose_type(&self) -> Option<PoseType> {
        PoseType::for_channel(&self.encoding, &self.type_name)
    }
}

/// What a bag holds, as listed before choosing its topics.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BagListing {
    /// Its topics, sorted by name.
    pub topics: Vec<TopicInfo>,
    /// For each file cut short, where and what it lost: the counts are of what it holds before the
    /// cut.
    pub cut_short: Vec<String>,
}
