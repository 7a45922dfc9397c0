//! One of the two streams `pushlab live` follows: its topic, how its messages are read, its latest
//! pose and how late it arrived.

use pushlab_core::live::{Channel, PoseReading, Stream};
use pushlab_core::recording::bag::PlanarPose;
use serde_json::json;

/// One of the two streams shown: its topic, how it is read, its latest pose.
pub(super) struct Watched {
    pub(super) stream: Stream,
    pub(super) role: &'static str,
    pub(super) topic: String,
    child: Option<String>,
    /// The channel bound to, once advertised.
    pub(super) channel: Option<u64>,
    reading: Option<PoseReading>,
    latest: Option<PlanarPose>,
    /// Receive time − header stamp of the latest, seconds.
    lag_s: Option<f64>,
    unreadable: usize,
}

impl Watched {
    pub(super) fn new(stream: Stream, spec: &str) -> Self {
        let role = match stream {
            Stream::Pusher => "pusher",
            Stream::Object => "object",
        };
        let (topic, child) = match spec.split_once(':') {
            Some((topic, child)) => (topic.to_owned(), Some(child.to_owned())),
            None => (spec.to_owned(), None),
        };
        Self {
            stream,
            role,
            topic,
            child,
            channel: None,
            reading: None,
            latest: None,
            lag_s: None,
            unreadable: 0,
        }
    }

    /// Binds to the advertised channel of its topic; why it cannot be read, in words.
    pub(super) fn bind(&mut self, channel: &Channel) -> Result<(), String> {
        let reading = PoseReading::for_channel(channel, self.child.as_deref())?;
        self.channel = Some(channel.id);
        self.reading = Some(reading);
        Ok(())
    }

    /// Reads one message of its channel, received at `now_ns`: the pose, if it holds one (an
    /// unreadable message is counted and said once).
    pub(super) fn take(&mut self, payload: &[u8], now_ns: u64) -> Option<PlanarPose> {
        let reading = self.reading.as_ref()?;
        match reading.read(payload) {
            Ok(Some(pose)) => {
                self.lag_s =
                    (pose.stamp_ns > 0).then_some((now_ns as f64 - pose.stamp_ns as f64) * 1e-9);
                self.latest = Some(pose);
                Some(pose)
            }
            Ok(None) => None,
            Err(why) => {
                if self.unreadable == 0 {
                    eprintln!("warning: {} {}: {why}", self.role, self.topic);
                }
                self.unreadable += 1;
                None
            }
        }
    }

    pub(super) fn text(&self) -> String {
        match self.latest {
            Some(p) => format!(
                "{} ({:.3}, {:.3}) m {:.1}°{}",
                self.role,
                p.x,
                p.y,
                p.yaw.to_degrees(),
                self.lag_s
                    .map(|l| format!(" {:.0} ms late", l * 1e3))
                    .unwrap_or_default()
            ),
            None => format!("{} -", self.role),
        }
    }

    pub(super) fn json(&self) -> serde_json::Value {
        match self.latest {
            Some(p) => json!({"stamp_ns": p.stamp_ns, "x": p.x, "y": p.y, "yaw": p.yaw,
                              "lag_s": self.lag_s, "unreadable": self.unreadable}),
            None => serde_json::Value::Null,
        }
    }
}
