//! One of the two streams a live session follows, the pusher or the object: its topic (and TF child
//! frame), the channel it is bound to on the connection now, how its messages are read, its latest
//! pose and how late that arrived. Bound **by topic name**: a server that restarts may number its
//! channels differently. A TF child frame is followed through its chain of parents
//! ([`LiveChain`]), with `/tf_static` read beside its topic.

use super::grid::Stream;
use super::pose::PoseReading;
use super::protocol::Channel;
use super::tf_chain::LiveChain;
use crate::recording::bag::{PlanarPose, TF_STATIC};

/// A stream followed (see the module documentation).
#[derive(Debug)]
pub struct Followed {
    stream: Stream,
    topic: String,
    child: Option<String>,
    /// The channel bound to on the connection now, once advertised.
    channel: Option<u64>,
    reading: Option<PoseReading>,
    /// A TF child frame's chain, kept across reconnects (its links are the robot's, not the
    /// connection's).
    chain: Option<LiveChain>,
    /// The `/tf_static` channel on the connection now, read for a TF child frame's chain.
    static_channel: Option<u64>,
    latest: Option<PlanarPose>,
    /// Receive time − header stamp of the latest, seconds.
    lag_s: Option<f64>,
    unreadable: usize,
}

/// What reading one message of a followed stream gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Reading {
    /// Its poses (none: a TF message about other frames, or a chain's pose waiting for a link;
    /// several: poses that waited), and sentences for the user (the chain followed).
    Poses {
        poses: Vec<PlanarPose>,
        said: Vec<String>,
    },
    /// A message that does not decode: why, said the first time ([`Followed::unreadable`] counts).
    Unreadable { first: bool, why: String },
}

impl Reading {
    fn poses(poses: Vec<PlanarPose>) -> Self {
        Self::Poses {
            poses,
            said: Vec::new(),
        }
    }
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
            chain: None,
            static_channel: None,
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
        if let PoseReading::Tf { child } = &reading
            && self.chain.is_none()
        {
            self.chain = Some(LiveChain::new(child, self.static_channel.is_some()));
        }
        self.channel = Some(channel.id);
        self.reading = Some(reading);
        Ok(())
    }

    /// Reads `/tf_static` on `channel` too when it follows a TF child frame (of another topic).
    pub fn bind_static(&mut self, channel: &Channel) {
        if channel.topic != TF_STATIC || self.topic == TF_STATIC || self.child.is_none() {
            return;
        }
        self.static_channel = Some(channel.id);
        if let Some(chain) = self.chain.as_mut() {
            chain.expect_static();
        }
    }

    /// Whether a message of `channel` is read by this stream (its topic's, or `/tf_static`).
    pub fn reads(&self, channel: u64) -> bool {
        self.channel == Some(channel) || self.static_channel == Some(channel)
    }

    /// Reads one message of `channel` (one it [`reads`](Self::reads)), logged at `log_time_ns`
    /// and received at `now_ns` (Unix nanoseconds).
    pub fn read(&mut self, channel: u64, payload: &[u8], log_time_ns: u64, now_ns: u64) -> Reading {
        let is_static = self.static_channel == Some(channel) && self.channel != Some(channel);
        let read = match (self.chain.as_mut(), self.reading.as_ref()) {
            (Some(chain), _) => chain
                .add(payload, log_time_ns, is_static)
                .map(|r| (r.poses, r.said)),
            (None, Some(reading)) => reading
                .read_single(payload)
                .map(|pose| (pose.into_iter().collect(), Vec::new())),
            (None, None) => Ok((Vec::new(), Vec::new())),
        };
        match read {
            Ok((poses, said)) => {
                if let Some(pose) = poses.last() {
                    self.lag_s = (pose.stamp_ns > 0)
                        .then_some((now_ns as f64 - pose.stamp_ns as f64) * 1e-9);
                    self.latest = Some(*pose);
                }
                match said.is_empty() {
                    true => Reading::poses(poses),
                    false => Reading::Poses { poses, said },
                }
            }
            Err(why) => {
                self.unreadable += 1;
                Reading::Unreadable {
                    first: self.unreadable == 1,
                    why,
                }
            }
        }
    }

    /// Poses of a TF chain that could not be composed at their time (a link not published then).
    pub fn dropped(&self) -> usize {
        self.chain.as_ref().map_or(0, LiveChain::dropped)
    }
}
