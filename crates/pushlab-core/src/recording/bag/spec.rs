//! How a user names a stream of poses in a bag: a topic, or a frame of a `/tf` tree.

/// A topic to read poses from, `TOPIC[:CHILD_FRAME]`; the child frame picks one frame of the
/// transform tree of a `tf2_msgs/msg/TFMessage` topic such as `/tf` (with `/tf_static`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TopicSpec {
    pub topic: String,
    pub child_frame: Option<String>,
}

impl std::str::FromStr for TopicSpec {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let (topic, child_frame) = match text.split_once(':') {
            Some((topic, frame)) => (topic, Some(frame.to_owned())),
            None => (text, None),
        };
        if topic.is_empty() || child_frame.as_deref() == Some("") {
            return Err(format!("'{text}': expected TOPIC or TOPIC:CHILD_FRAME"));
        }
        Ok(Self {
            topic: topic.to_owned(),
            child_frame,
        })
    }
}

impl std::fmt::Display for TopicSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.child_frame {
            Some(frame) => write!(f, "{}:{frame}", self.topic),
            None => write!(f, "{}", self.topic),
        }
    }
}
