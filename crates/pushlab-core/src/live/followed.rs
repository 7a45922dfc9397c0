//! One of the two streams a live session follows, the pusher or the object: its topic (and TF child
//! frame), the channel it is bound to on the connection now, how its messages are read, its latest
//! pose and how late that arrived. Bound **by topic name**: a server that restarts may number its
//! channels differently.

use super::grid::Stream;
use super::pose::PoseReading;
use super::protocol::Channel;
use crate::recording::bag::PlanarPose;

/// A stream followed (see the module documentation).
#[derive(Debug)]
pub struct Followed {
    stream: Stream,
    topic: String,
    child: Option<String>,
    /// The channel bound to on the connection now, once advertised.
    channel: Option<u64>,
    reading: Option<PoseReading>,
    latest: Option<PlanarPose>,
    /// Receive time − header stamp of the latest, seconds.
    lag_s: Option<f64>,
    unreadable: usize,
}

/// What reading one message of a followed stream gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Reading {
    /// A pose.
    Pose(PlanarPose),
    /// A message without the pose asked for (a TF message about other frames).
    Nothing,
    /// A message that does not decode: why, said the first time ([`Followed::unreadable`] counts).
    Unreadable { first: bool, why: String },
}

impl Followed {
    /// The stream `spec` names: `TOPIC`, or `TOPIC:CHILD_FRAME` for a TF topic such as `/tf`.
    pub fn new(stream: Stream, spec: &str) -> Self {
        let (topic, child) = match spec.split_once(':') {
            Some((topic, child)) => (topic.to_owned(), Some(child.to_owned())),
            None => (spec.to_owned(), None),
        };
        Self {
            stream,
            topic,
            child,
            channel: None,
            reading: None,
            latest: None,
            lag_s: None,
            unreadable: 0,
        }
    }

    pub fn stream(&self) -> Stream {
        self.stream
    }

    /// "pusher" or "object", for messages.
    pub fn role(&self) -> &'static str {
        self.stream.name()
    }

    pub fn topic(&self) -> &str {
        &self.topic
    }

    /// The channel it is bound to now.
    pub fn channel(&self) -> Option<u64> {
        self.channel
    }

    /// The latest pose read.
    pub fn latest(&self) -> Option<&PlanarPose> {
        self.latest.as_ref()
    }

    /// How late the latest pose arrived (receive time − its stamp), seconds.
    pub fn lag_s(&self) -> Option<f64> {
        self.lag_s
    }

    /// Messages that did not decode.
    pub fn unreadable(&self) -> usize {
        self.unreadable
    }

    /// Binds to the advertised channel of its topic; why it cannot be read, in words.
    pub fn bind(&mut self, channel: &Channel) -> Result<(), String> {
        let reading = PoseReading::for_channel(channel, self.child.as_deref())?;
        self.channel = Some(channel.id);
        self.reading = Some(reading);
        Ok(())
    }

    /// Reads one message of its channel, received at `now_ns` (Unix nanoseconds).
    pub fn read(&mut self, payload: &[u8], now_ns: u64) -> Reading {
        let Some(reading) = self.reading.as_ref() else {
            return Reading::Nothing;
        };
        match reading.read(payload) {
            Ok(Some(pose)) => {
                self.lag_s =
                    (pose.stamp_ns > 0).then_some((now_ns as f64 - pose.stamp_ns as f64) * 1e-9);
                self.latest = Some(pose);
                Reading::Pose(pose)
            }
            Ok(None) => Reading::Nothing,
            Err(why) => {
                self.unreadable += 1;
                Reading::Unreadable {
                    first: self.unreadable == 1,
                    why,
                }
            }
        }
    }
}
