//! A live session with a robot's Foxglove WebSocket server, as `pushlab live` and the app's
//! File → Connect to a live robot… both run it: connect, wait for the pusher's and the object's
//! topics to be advertised, bind them by topic name, subscribe to every channel (now and later),
//! write every message received to the recording as it arrives (chunks ended once a second), read
//! the two streams' poses, and when the server goes away connect again with backoff until it comes
//! back or the session ends — the topics followed by name, since a restarted server may number its
//! channels anew. One copy of these rules, so that the CLI and the app cannot drift.
//!
//! Blocking, on the caller's thread (a worker's in the app); every wait asks `stop` at least every
//! [`READ_TIMEOUT`].

mod commands;

use std::collections::VecDeque;
use std::path::Path;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use super::client::{LiveClient, LiveError, LiveEvent};
use super::followed::{Followed, Reading};
use super::grid::Stream;
use super::recorder::{RecordError, Recorded, Recorder};
use crate::recording::bag::{
    ImageKind, PlanarPose, PoseType, TF_STATIC, TopicInfo, decode_image_message, decode_tf,
};
use crate::recording::camera::{RgbaImage, decode as decode_image};

/// How long to wait for the server, and at most between two looks at `stop`.
pub const READ_TIMEOUT: Duration = Duration::from_millis(100);
/// How long the topics asked for may take to be advertised.
const ADVERTISE_WAIT: Duration = Duration::from_secs(5);
/// The first wait before connecting again, doubled after each failed attempt up to the longest.
const FIRST_RETRY: Duration = Duration::from_millis(250);
const LONGEST_RETRY: Duration = Duration::from_secs(4);
/// How often the recording's chunk is ended, so that a crash loses at most this much.
const FLUSH_EVERY: Duration = Duration::from_secs(1);

/// Why a live session could not start or go on; each names the server or the file.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error(transparent)]
    Live(#[from] LiveError),
    #[error(transparent)]
    Record(#[from] RecordError),
    /// The server cannot take the commands a controller would send it.
    #[error(transparent)]
    Refused(#[from] super::command::CommandRefused),
    /// A topic asked for that the server did not advertise in time.
    #[error("{url}: no topic {topic} advertised within {} s; the server's topics: {topics}", ADVERTISE_WAIT.as_secs())]
    NotAdvertised {
        url: String,
        topic: String,
        topics: String,
    },
    /// A topic asked for whose messages cannot give a pose (its type, a TF topic without a child
    /// frame): the choice is wrong, so connecting again would not help.
    #[error("the {role} topic {topic}: {why}")]
    Unreadable {
        role: &'static str,
        topic: String,
        why: String,
    },
}

/// What happened in a session, one thing at a time.
#[derive(Clone, Debug, PartialEq)]
pub enum SessionEvent {
    /// A pose of the pusher or the object, with the server's log time of its message.
    Pose {
        stream: Stream,
        pose: PlanarPose,
        log_time_ns: u64,
    },
    /// Something the user should read: a topic withdrawn or advertised again, a message that does
    /// not decode (the first of its stream; the rest counted), the server's own status messages.
    Said(String),
    /// The connection ended; the next call connects again (with backoff) until it is back.
    Lost(String),
    /// Connected again after `after_s` seconds and `attempts` attempts: a gap in the recording.
    Reconnected { after_s: f64, attempts: usize },
    /// A camera message (`CompressedImage` or `Image`), when asked for ([`LiveSession::show_images`]):
    /// still encoded, so that a caller that shows only the latest decodes only that one.
    Image {
        topic: String,
        kind: ImageKind,
        log_time_ns: u64,
        payload: Vec<u8>,
    },
}

/// A session (see the module documentation).
pub struct LiveSession {
    url: String,
    /// `None` while the connection is lost.
    client: Option<LiveClient>,
    server: Option<String>,
    followed: [Followed; 2],
    recorder: Option<Recorder>,
    messages: u64,
    last_flush: Instant,
    /// When the connection was lost, while it is.
    lost_at: Option<Instant>,
    /// Events of one message still to hand out (one TF message may hold both streams' poses).
    queued: VecDeque<SessionEvent>,
    /// Whether camera messages are handed out too.
    images: bool,
    /// The topic the pusher's target is sent on, once advertised (again on each reconnect).
    command: Option<super::command::CommandTopic>,
    commands_sent: u64,
    /// How long a read waits at most, when not [`READ_TIMEOUT`].
    read_timeout: Option<Duration>,
}

/// Unix time now, nanoseconds: what a pose's lag is measured against.
pub fn unix_now_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

impl LiveSession {
    /// Connects to `url` and follows the pusher and the object (`TOPIC` or `TOPIC:CHILD_FRAME`),
    /// recording every message to `record` (a new file) when given. Fails at once with the reason:
    /// a wrong address or topic should not wait.
    pub fn open(
        url: &str,
        pusher: &str,
        object: &str,
        record: Option<&Path>,
        stop: &dyn Fn() -> bool,
    ) -> Result<Self, SessionError> {
        let recorder = record.map(Recorder::create).transpose()?;
        let mut followed = [
            Followed::new(Stream::Pusher, pusher),
            Followed::new(Stream::Object, object),
        ];
        let (client, server) = connect(url, &mut followed, stop)?;
        Ok(Self {
            url: url.to_owned(),
            client: Some(client),
            server,
            followed,
            recorder,
            messages: 0,
            last_flush: Instant::now(),
            lost_at: None,
            queued: VecDeque::new(),
            images: false,
            command: None,
            commands_sent: 0,
            read_timeout: None,
        })
    }

    /// Hands out every camera message as [`SessionEvent::Image`] from now on (the app's camera
    /// panel; `pushlab live` only records them).
    pub fn show_images(&mut self) {
        self.images = true;
    }

    /// Reads wait at most `timeout` from now on, on this connection and the next ones: a
    /// controller must look at its clock more often than [`READ_TIMEOUT`].
    pub fn read_at_most(&mut self, timeout: Duration) -> Result<(), SessionError> {
        self.read_timeout = Some(timeout);
        if let Some(client) = self.client.as_mut() {
            client.set_read_timeout(timeout)?;
        }
        Ok(())
    }

    /// The server's address.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The server's name, if it said one.
    pub fn server(&self) -> Option<&str> {
        self.server.as_deref()
    }

    /// The subprotocol agreed, while connected.
    pub fn subprotocol(&self) -> Option<&str> {
        self.client.as_ref().map(LiveClient::subprotocol)
    }

    /// The channels advertised now (none while the connection is lost).
    pub fn channels(&self) -> usize {
        self.client.as_ref().map_or(0, |c| c.channels().count())
    }

    /// The pusher and the object, in that order.
    pub fn followed(&self) -> &[Followed; 2] {
        &self.followed
    }

    /// Messages received so far, on every channel (each one recorded, when recording).
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// The file recorded to, if any.
    pub fn recording(&self) -> Option<&Path> {
        self.recorder.as_ref().map(Recorder::path)
    }

    /// Whether the connection is lost now (being connected again).
    pub fn is_lost(&self) -> bool {
        self.client.is_none()
    }

    /// The next thing that happened, or `None` when nothing did within [`READ_TIMEOUT`] (or
    /// `stop` said so while connecting again). Errors end the session: the recording cannot be
    /// written, or a topic's type changed to one that cannot be read.
    pub fn next(&mut self, stop: &dyn Fn() -> bool) -> Result<Option<SessionEvent>, SessionError> {
        if let Some(event) = self.queued.pop_front() {
            return Ok(Some(event));
        }
        self.flush_when_due()?;
        let Some(client) = self.client.as_mut() else {
            return self.reconnect(stop);
        };
        match client.next_event() {
            Ok(None) | Ok(Some(LiveEvent::ServerInfo { .. })) => Ok(None),
            Ok(Some(LiveEvent::Message {
                channel,
                log_time_ns,
                payload,
            })) => {
                self.messages += 1;
                if let (Some(recorder), Some(c)) = (self.recorder.as_mut(), client.channel(channel))
                {
                    recorder.write(c, log_time_ns, &payload)?;
                }
                let now = unix_now_ns();
                if self.images
                    && let Some(c) = client.channel(channel)
                    && let Some(kind) = ImageKind::from_schema(&c.schema_name)
                    && c.encoding == "cdr"
                {
                    return Ok(Some(SessionEvent::Image {
                        topic: c.topic.clone(),
                        kind,
                        log_time_ns,
                        payload,
                    }));
                }
                for f in (self.followed.iter_mut()).filter(|f| f.reads(channel)) {
                    match f.read(channel, &payload, log_time_ns, now) {
                        Reading::Poses { poses, said } => {
                            let said = said.into_iter().map(|s| {
                                SessionEvent::Said(format!("{} {}: {s}", f.role(), f.topic()))
                            });
                            self.queued.extend(said);
                            self.queued.extend(poses.into_iter().map(|pose| SessionEvent::Pose {
                                stream: f.stream(),
                                pose,
                                log_time_ns,
                            }));
                        }
                        Reading::Unreadable { first: false, .. } => {}
                        Reading::Unreadable { first: true, why } => {
                            self.queued.push_back(SessionEvent::Said(format!(
                                "{} {}: {why} (this and every such message after it left out, counted)",
                                f.role(),
                                f.topic()
                            )))
                        }
                    }
                }
                Ok(self.queued.pop_front())
            }
            Ok(Some(LiveEvent::Advertised(channels))) => {
                for c in channels {
                    client.subscribe(c.id)?;
                    for f in self.followed.iter_mut() {
                        f.bind_static(&c);
                    }
                    // A topic advertised again (its node restarted) is followed on its new channel.
                    for f in (self.followed.iter_mut()).filter(|f| f.topic() == c.topic) {
                        if f.channel() != Some(c.id) {
                            let said = match f.bind(&c) {
                                Ok(()) => format!(
                                    "the server advertised the {} topic {} again: following it",
                                    f.role(),
                                    f.topic()
                                ),
                                Err(why) => format!("{} {}: {why}", f.role(), f.topic()),
                            };
                            self.queued.push_back(SessionEvent::Said(said));
                        }
                    }
                }
                Ok(self.queued.pop_front())
            }
            Ok(Some(LiveEvent::Unadvertised(ids))) => {
                for f in
                    (self.followed.iter()).filter(|f| f.channel().is_some_and(|c| ids.contains(&c)))
                {
                    self.queued.push_back(SessionEvent::Said(format!(
                        "the server withdrew the {} topic {}",
                        f.role(),
                        f.topic()
                    )));
                }
                Ok(self.queued.pop_front())
            }
            Ok(Some(LiveEvent::Status { level, message })) => {
                let level = ["info", "warning", "error"]
                    .get(usize::from(level))
                    .unwrap_or(&"status");
                Ok(Some(SessionEvent::Said(format!(
                    "server {level}: {message}"
                ))))
            }
            Err(e) => {
                // What came before the loss is kept whatever happens next.
                if let Some(recorder) = self.recorder.as_mut() {
                    recorder.flush()?;
                }
                self.client = None;
                self.lost_at = Some(Instant::now());
                Ok(Some(SessionEvent::Lost(e.to_string())))
            }
        }
    }

    /// Connects again, waiting longer after each failed attempt, until it succeeds or `stop`
    /// says the session is over (`None`). A topic the server no longer has is one more failed
    /// attempt; a topic of a type that cannot be read ends it.
    fn reconnect(&mut self, stop: &dyn Fn() -> bool) -> Result<Option<SessionEvent>, SessionError> {
        let lost_at = *self.lost_at.get_or_insert_with(Instant::now);
        let mut wait = FIRST_RETRY;
        let mut attempts = 0;
        loop {
            let until = Instant::now() + wait;
            while Instant::now() < until {
                if stop() {
                    return Ok(None);
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            attempts += 1;
            match connect(&self.url, &mut self.followed, stop) {
                Ok((client, server)) => {
                    self.client = Some(client);
                    self.server = server.or(self.server.take());
                    self.lost_at = None;
                    if let (Some(timeout), Some(client)) = (self.read_timeout, self.client.as_mut())
                    {
                        client.set_read_timeout(timeout)?;
                    }
                    self.advertise_command_again()?;
                    return Ok(Some(SessionEvent::Reconnected {
                        after_s: lost_at.elapsed().as_secs_f64(),
                        attempts,
                    }));
                }
                Err(e @ SessionError::Unreadable { .. }) => return Err(e),
                Err(_) if stop() => return Ok(None),
                Err(_) => wait = (wait * 2).min(LONGEST_RETRY),
            }
        }
    }

    fn flush_when_due(&mut self) -> Result<(), SessionError> {
        if self.last_flush.elapsed() >= FLUSH_EVERY {
            self.last_flush = Instant::now();
            if let Some(recorder) = self.recorder.as_mut() {
                recorder.flush()?;
            }
        }
        Ok(())
    }

    /// Ends the session: the recording closed cleanly (summary and indexes), the connection closed
    /// politely. What was recorded, when recording.
    pub fn finish(self) -> Result<Option<Recorded>, SessionError> {
        if let Some(client) = self.client {
            client.close();
        }
        Ok(self.recorder.map(Recorder::finish).transpose()?)
    }
}

/// Connects to `url` and binds `followed` to the channels of their topics (`stop` asked while
/// waiting for them to be advertised), then subscribes to every channel. The server's name, if it
/// said one.
fn connect(
    url: &str,
    followed: &mut [Followed; 2],
    stop: &dyn Fn() -> bool,
) -> Result<(LiveClient, Option<String>), SessionError> {
    let mut client = LiveClient::connect(url, READ_TIMEOUT)?;
    let asked = Instant::now();
    let mut server = None;
    while (followed.iter()).any(|f| client.channel_of(f.topic()).is_none())
        && asked.elapsed() < ADVERTISE_WAIT
        && !stop()
    {
        if let Some(LiveEvent::ServerInfo { name }) = client.next_event()? {
            server = named(name);
        }
    }
    for f in followed.iter_mut() {
        let Some(channel) = client.channel_of(f.topic()).cloned() else {
            let topics: Vec<String> = (client.channels())
                .map(|c| format!("{} ({})", c.topic, c.schema_name))
                .collect();
            return Err(SessionError::NotAdvertised {
                url: url.to_owned(),
                topic: f.topic().to_owned(),
                topics: if topics.is_empty() {
                    "none".to_owned()
                } else {
                    topics.join(", ")
                },
            });
        };
        if let Some(fixed) = client.channel_of(TF_STATIC) {
            f.bind_static(fixed);
        }
        f.bind(&channel).map_err(|why| SessionError::Unreadable {
            role: f.role(),
            topic: f.topic().to_owned(),
            why,
        })?;
    }
    let ids: Vec<u64> = client.channels().map(|c| c.id).collect();
    for id in ids {
        client.subscribe(id)?;
    }
    Ok((client, server))
}

/// The picture a camera message of a live session holds, decoded, with its header stamp; why not,
/// in words.
pub fn decode_live_image(kind: ImageKind, payload: &[u8]) -> Result<(u64, RgbaImage), String> {
    let (stamp, encoded) = decode_image_message(kind, payload).map_err(|e| e.to_string())?;
    let image = decode_image(&encoded).map_err(|e| e.to_string())?;
    Ok((stamp, image))
}

/// What a server offers, for choosing the pusher and the object as for a bag: its name and each
/// channel as a bag's topic (type, encoding, and for a TF topic the child frames its messages
/// carried while listening for `listen`), so that the bag form's rules — the pose streams offered
/// and the pre-selection by name (`recording::bag::choice`) — apply unchanged.
pub fn list_topics(
    url: &str,
    listen: Duration,
    stop: &dyn Fn() -> bool,
) -> Result<(Option<String>, Vec<TopicInfo>), SessionError> {
    let mut client = LiveClient::connect(url, READ_TIMEOUT)?;
    let started = Instant::now();
    let mut server = None;
    let mut frames: Vec<(u64, Vec<String>)> = Vec::new();
    while started.elapsed() < listen && !stop() {
        match client.next_event()? {
            Some(LiveEvent::ServerInfo { name }) => server = named(name),
            Some(LiveEvent::Advertised(channels)) => {
                for c in channels {
                    if PoseType::from_schema(&c.schema_name) == Some(PoseType::TfMessage) {
                        client.subscribe(c.id)?;
                    }
                }
            }
            Some(LiveEvent::Message {
                channel, payload, ..
            }) => {
                let at = match frames.iter().position(|(id, _)| *id == channel) {
                    Some(at) => at,
                    None => {
                        frames.push((channel, Vec::new()));
                        frames.len() - 1
                    }
                };
                let seen = &mut frames[at].1;
                // A message that does not decode lists nothing; the session says why later.
                let _ = decode_tf(&payload, |t| {
                    let child = String::from_utf8_lossy(t.child).into_owned();
                    if !seen.contains(&child) {
                        seen.push(child);
                    }
                });
            }
            _ => {}
        }
    }
    let topics = (client.channels())
        .map(|c| {
            let mut info = TopicInfo {
                topic: c.topic.clone(),
                type_name: c.schema_name.clone(),
                encoding: c.encoding.clone(),
                count: 0,
                first_ns: 0,
                last_ns: 0,
                child_frames: Vec::new(),
                camera: None,
            };
            for (_, seen) in frames.iter().filter(|(id, _)| *id == c.id) {
                for frame in seen {
                    info.add_frame(frame);
                }
            }
            info
        })
        .collect();
    client.close();
    Ok((server, topics))
}
/// A server's name as it gave it, or none where it gave an empty one (the Foxglove SDK's server
/// unless named), so that what says it never prints "( , foxglove.sdk.v1)".
fn named(name: String) -> Option<String> {
    (!name.trim().is_empty()).then_some(name)
}
