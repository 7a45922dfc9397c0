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
    /// How late the latest pose arrived.
    lag: Option<Lag>,
    /// Receive time − stamp of the stream's first stamped pose, nanoseconds: where its stamps are
    /// not wall-clock time, lag is counted from there.
    first_offset_ns: Option<f64>,
    unreadable: usize,
}

/// Stamps further than this from the receive clock are not wall-clock time (a recording's clock
/// replayed, a robot's time since boot): an hour, far beyond any network's delay or clock skew.
const NOT_WALL_CLOCK_S: f64 = 3600.0;

/// How late a pose arrived. With wall-clock stamps, receive time − stamp. With stamps on another
/// clock (a replayed recording's, a robot's since boot), that difference is the clocks' distance
/// (a replay of a 2023 bag read 96 million seconds "late"), so the lag is counted from the stream's
/// first pose instead: how much later than the first this one arrived, against the time between
/// their stamps — a link falling behind still shows, a clock offset does not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lag {
    pub seconds: f64,
    /// Whether the stamps are wall-clock time (the lag is receive time − stamp).
    pub wall_clock: bool,
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
            lag: None,
            first_offset_ns: None,
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

    /// How late the latest pose arrived (see [`Lag`]).
    pub fn lag(&self) -> Option<Lag> {
        self.lag
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
                    self.lag = self.lag_of(pose.stamp_ns, now_ns);
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

    /// The lag of a pose stamped `stamp_ns` received at `now_ns` (see [`Lag`]); none unstamped.
    fn lag_of(&mut self, stamp_ns: u64, now_ns: u64) -> Option<Lag> {
        if stamp_ns == 0 {
            return None;
        }
        let offset_ns = now_ns as f64 - stamp_ns as f64;
        // A stamp before the latest's starts over (a replay looping, a robot restarted).
        if self.latest.is_some_and(|latest| stamp_ns < latest.stamp_ns) {
            self.first_offset_ns = None;
        }
        let first = *self.first_offset_ns.get_or_insert(offset_ns);
        let wall_clock = first.abs() * 1e-9 < NOT_WALL_CLOCK_S;
        let seconds = if wall_clock {
            offset_ns * 1e-9
        } else {
            (offset_ns - first) * 1e-9
        };
        Some(Lag {
            seconds,
            wall_clock,
        })
    }

    /// Poses of a TF chain that could not be composed at their time (a link not published then).
    pub fn dropped(&self) -> usize {
        self.chain.as_ref().map_or(0, LiveChain::dropped)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    const NOW: u64 = 1_796_000_000_000_000_000; // December 2026, Unix ns

    fn followed() -> Followed {
        Followed::new(Stream::Object, "/object")
    }

    #[test]
    fn wall_clock_stamps_lag_by_receive_time_minus_stamp() {
        let mut f = followed();
        let lag = f.lag_of(NOW - 20_000_000, NOW).unwrap();
        assert!(lag.wall_clock);
        assert!((lag.seconds - 0.020).abs() < 1e-9, "{lag:?}");
    }

    #[test]
    fn stamps_on_another_clock_lag_from_the_first_pose() {
        // A 2023 recording replayed now: 96 million seconds between the clocks.
        let stamp = NOW - 96_294_783_000_000_000;
        let mut f = followed();
        let first = f.lag_of(stamp, NOW).unwrap();
        assert!(!first.wall_clock);
        assert_eq!(first.seconds, 0.0);
        // 100 ms of stamps later, received 150 ms later: 50 ms behind the first.
        let later = f.lag_of(stamp + 100_000_000, NOW + 150_000_000).unwrap();
        assert!(!later.wall_clock);
        assert!((later.seconds - 0.050).abs() < 1e-6, "{later:?}");
    }

    #[test]
    fn an_unstamped_pose_has_no_lag() {
        assert_eq!(followed().lag_of(0, NOW), None);
    }
}
