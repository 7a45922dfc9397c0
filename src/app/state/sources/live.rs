//! File → Connect to a live robot…: the form (the server's address, the pusher's and the object's
//! topics, the object's `setting.json`, the file to record to), remembered per server address once
//! it connected; and the session itself, the core's [`LiveSession`] on a worker thread — the same
//! session `pushlab live` runs — putting both pose streams on the grid a bag import makes
//! ([`LiveGrid`]).
//!
//! The worker hands its frames to the UI thread through an inbox the UI empties every frame: frames
//! are never dropped (online learning needs every one, and the recording has every message), but
//! everything else there — the message count, how late the poses arrive, the connection's state —
//! is the latest only. What the UI does with the frames (the recording growing, learning, the
//! timeline following the live edge) is `live_feed`'s.

#[cfg(not(target_arch = "wasm32"))]
mod commanding;
#[cfg(not(target_arch = "wasm32"))]
pub mod worker;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use pushlab_core::recording::camera::RgbaImage;
use pushlab_core::trajectory::Frame;
use serde::{Deserialize, Serialize};

use crate::app::state::job::{Job, take_ended};
use crate::app::state::recordings::session::RecordingId;
use crate::app::state::sources::driving::Driving;
pub use crate::app::state::sources::live_drive::{
    DriveChoice, DriveCommand, DriveStatus, LiveDrive, ToWorker,
};
use pushlab_core::recording::bag::{TopicInfo, TopicSpec, choice};

/// What the form asks for; remembered per server address once a session with it started.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LiveChoice {
    /// `ws://HOST:PORT` (foxglove_bridge and the Foxglove SDK listen on 8765).
    pub url: String,
    /// `TOPIC`, or `TOPIC:CHILD_FRAME` for a TF topic such as `/tf`.
    pub pusher: String,
    pub object: String,
    /// The object's outline and the pusher's radius, as for a bag.
    pub setting: PathBuf,
    /// A new MCAP file every message received is written to; empty: not recorded.
    pub record: PathBuf,
    /// The grid's rate, Hz; `None`: the rate the model was trained at.
    pub rate_hz: Option<f64>,
    /// Whether, and how, the controller drives the robot (boxed: most sessions only watch, and
    /// every form edit carries the choice).
    pub drive: Box<DriveChoice>,
}

/// The form being filled in, with why the last Connect failed.
#[derive(Clone, Debug, PartialEq)]
pub struct LiveForm {
    pub choice: LiveChoice,
    pub error: Option<String>,
    /// The pose streams the server offers (as a bag's: topics, and TF child frames), once listed;
    /// or why they could not be.
    pub streams: Option<Result<Vec<TopicSpec>, String>>,
}

/// How long listing a server's topics listens for TF child frames.
#[cfg(not(target_arch = "wasm32"))]
const LISTEN: std::time::Duration = std::time::Duration::from_millis(1500);

/// A server's name and topics, listed off the UI thread.
type Listed = Result<(Option<String>, Vec<TopicInfo>), String>;

/// Everything the Connect form and the live session do.
#[derive(Clone, Debug, PartialEq)]
pub enum LiveCommand {
    /// Open the form, filled in with the last server's choice.
    OpenForm,
    /// The form as the user edited it; the choice remembered for its address fills it in when the
    /// address changes to one connected to before.
    Edit(LiveChoice),
    CloseForm,
    /// Connect with the form's choice.
    Connect,
    /// List the pose streams the form's server offers, to choose from as for a bag.
    ListTopics,
    /// End the session: the recording closed cleanly; the push stays open to replay.
    Disconnect,
    /// Show the newest frame again and follow it (after scrubbing back while live).
    BackToLive,
    /// The drive's buttons (a session connected with Drive on).
    Drive(DriveCommand),
}

/// The connection as the worker last said it.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Link {
    #[default]
    Connecting,
    Connected {
        server: String,
    },
    /// Lost: connecting again, with backoff.
    Lost {
        why: String,
    },
    /// The worker ended: why, if it failed; what was recorded.
    Ended {
        error: Option<String>,
        recorded: Option<String>,
    },
}

/// What the worker hands over: what is taken once, and what is only the latest.
#[derive(Debug, Default)]
pub struct Inbox {
    pub handed: Handed,
    pub latest: Latest,
    /// What the UI hands the worker: the drive's targets and the user's asks.
    pub to_worker: ToWorker,
}

/// What the UI takes out of the inbox every frame.
#[derive(Debug, Default)]
pub struct Handed {
    /// Frames made since the UI last looked, in order: never dropped.
    pub frames: Vec<Frame>,
    /// Sentences for the user (a topic withdrawn, a message that does not decode, a reconnect).
    pub said: Vec<String>,
    /// Connections lost and made again, each once its frames are handed over.
    pub gaps: Vec<Gap>,
    /// The newest picture of each camera topic, decoded (latest wins until the UI takes it).
    pub images: BTreeMap<String, LiveImage>,
}

/// What the worker says of the session now; the UI copies it every frame.
#[derive(Clone, Debug, Default)]
pub struct Latest {
    pub link: Link,
    pub messages: u64,
    /// How late the pusher's and the object's latest poses arrived.
    pub lag: [Option<pushlab_core::live::Lag>; 2],
    /// Poses the grid refused (out of order, bad values).
    pub refused: usize,
    /// Camera messages per topic that came faster than the UI took them: recorded, not shown.
    pub images_dropped: BTreeMap<String, u64>,
    /// The drive, when the session drives the robot.
    pub drive: Option<DriveStatus>,
}

/// A connection lost and made again: the push's frames over that time are interpolated between the
/// last poses before and the first after (as the recording's import interpolates them), so the
/// timeline marks them.
#[derive(Clone, Debug, PartialEq)]
pub struct Gap {
    /// The frames interpolated across the gap: from the first frame after the last one made before
    /// the loss to the first frame made from poses after it.
    pub frames: std::ops::Range<usize>,
    /// How long the connection was away, seconds (wall clock).
    pub away_s: f64,
}

/// Each live camera's newest picture, and the pictures each dropped from the display.
pub type LiveImages<'a> = (&'a BTreeMap<String, LiveImage>, &'a BTreeMap<String, u64>);

/// The newest picture of a live camera, decoded on the worker.
#[derive(Clone, Debug)]
pub struct LiveImage {
    /// Its header stamp (Unix ns).
    pub stamp_ns: u64,
    /// Counts the pictures of its topic shown, so the panel uploads each one once.
    pub number: u64,
    pub image: Result<Arc<RgbaImage>, String>,
}

/// The worker's half: the inbox and the stop flag.
#[derive(Clone, Debug, Default)]
pub struct WorkerLink {
    inbox: Arc<Mutex<Inbox>>,
    stop: Arc<AtomicBool>,
}

impl WorkerLink {
    /// Changes the inbox (a poisoned lock is taken as it is: the inbox holds plain data).
    pub fn with<R>(&self, f: impl FnOnce(&mut Inbox) -> R) -> R {
        f(&mut self.inbox.lock().unwrap_or_else(PoisonError::into_inner))
    }

    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// The form, the choices remembered, and the session running.
#[derive(Default)]
pub struct Live {
    form: Option<LiveForm>,
    /// The choice of each server connected to, by address.
    remembered: BTreeMap<String, LiveChoice>,
    /// The address connected to last: what the form opens with.
    last_url: Option<String>,
    session: Option<Running>,
    /// The form's server being listed: its address and the job.
    listing: Option<(String, Job<Listed>)>,
}

/// A session running (or ended and still shown).
#[derive(Debug)]
pub struct Running {
    pub choice: LiveChoice,
    pub link: WorkerLink,
    /// The latest the worker said.
    pub latest: Latest,
    /// Where the connection was lost and made again.
    pub gaps: Vec<Gap>,
    /// Frames handed over so far.
    pub frames: usize,
    /// The recording the frames go to.
    pub recording: RecordingId,
    /// The newest picture of each camera topic taken from the worker.
    pub images: BTreeMap<String, LiveImage>,
    /// Whether connecting, and how the session ended, were said.
    pub said_connected: bool,
    pub said_end: bool,
    /// The controller driving the robot, when Drive was on.
    pub drive: Option<LiveDrive>,
}

impl Live {
    /// The choices remembered per server and the last address, as persisted.
    pub fn new(remembered: BTreeMap<String, LiveChoice>, last_url: Option<String>) -> Self {
        Self {
            form: None,
            remembered,
            last_url,
            session: None,
            listing: None,
        }
    }

    pub fn remembered(&self) -> &BTreeMap<String, LiveChoice> {
        &self.remembered
    }

    pub fn last_url(&self) -> Option<&str> {
        self.last_url.as_deref()
    }

    pub fn form(&self) -> Option<&LiveForm> {
        self.form.as_ref()
    }

    pub fn running(&self) -> Option<&Running> {
        self.session.as_ref()
    }

    pub(in crate::app::state) fn running_mut(&mut self) -> Option<&mut Running> {
        self.session.as_mut()
    }

    /// The controller driving the robot, while the session runs.
    pub(in crate::app::state) fn driving_mut(&mut self) -> Option<&mut Driving> {
        (self.session.as_mut())
            .and_then(|s| s.drive.as_mut())
            .map(|d| &mut d.driving)
    }

    /// Whether a session's worker is still running (connected, connecting or reconnecting).
    pub fn is_live(&self) -> bool {
        (self.session.as_ref()).is_some_and(|s| !matches!(s.latest.link, Link::Ended { .. }))
    }

    /// Applies the form's own commands; Connect, Disconnect and Back to live need the whole state
    /// (`live_feed`).
    pub(in crate::app::state) fn apply_form(&mut self, command: &LiveCommand) {
        match command {
            LiveCommand::OpenForm => {
                let choice = (self.last_url.as_ref())
                    .and_then(|url| self.remembered.get(url))
                    .cloned()
                    .map(|mut c| {
                        c.record = next_free(&c.record);
                        c
                    })
                    .unwrap_or_else(|| LiveChoice {
                        url: "ws://localhost:8765".to_owned(),
                        ..LiveChoice::default()
                    });
                self.form = Some(LiveForm {
                    choice,
                    error: None,
                    streams: None,
                });
            }
            LiveCommand::Edit(choice) => {
                let Some(form) = &mut self.form else { return };
                let mut choice = choice.clone();
                if choice.url != form.choice.url
                    && let Some(known) = self.remembered.get(&choice.url)
                {
                    choice = LiveChoice {
                        record: next_free(&known.record),
                        ..known.clone()
                    };
                }
                form.choice = choice;
            }
            LiveCommand::CloseForm => {
                self.form = None;
                self.listing = None;
            }
            LiveCommand::ListTopics => self.list_topics(),
            LiveCommand::Connect
            | LiveCommand::Disconnect
            | LiveCommand::BackToLive
            | LiveCommand::Drive(_) => {}
        }
    }

    /// Lists the form's server's topics on a worker (a page has no sockets: said on the form).
    fn list_topics(&mut self) {
        let Some(form) = &mut self.form else { return };
        let url = form.choice.url.clone();
        if cfg!(target_arch = "wasm32") {
            form.streams = Some(Err(NOT_IN_A_PAGE.to_owned()));
            return;
        }
        form.streams = None;
        let job = Job::spawn(move |context| Some(list(&url, &|| context.is_cancelled())));
        self.listing = Some((form.choice.url.clone(), job));
    }

    /// Whether the form's server is being listed.
    pub fn is_listing(&self) -> bool {
        self.listing.is_some()
    }

    /// Takes a finished listing into the form: the streams offered, and the pusher and object
    /// pre-selected by name as for a bag where the form has none yet.
    pub(in crate::app::state) fn poll_listing(&mut self) {
        let Some((url, listed)) = take_ended(&mut self.listing) else {
            return;
        };
        let Some(form) = self.form.as_mut().filter(|f| f.choice.url == url) else {
            return;
        };
        form.streams = Some(match listed {
            Some(Ok((_, topics))) => {
                let (pusher, object) = choice::suggest(&topics);
                let choice = &mut form.choice;
                if choice.pusher.trim().is_empty()
                    && let Some(pusher) = pusher
                {
                    choice.pusher = pusher.to_string();
                }
                if choice.object.trim().is_empty()
                    && let Some(object) = object
                {
                    choice.object = object.to_string();
                }
                Ok(choice::candidates(&topics))
            }
            Some(Err(why)) => Err(why),
            None => Err("listing stopped".to_owned()),
        });
    }

    /// The form's choice, to connect with.
    pub(in crate::app::state) fn form_choice(&self) -> Option<LiveChoice> {
        self.form.as_ref().map(|f| f.choice.clone())
    }

    /// Connect failed before the session started: said on the form.
    pub(in crate::app::state) fn refuse(&mut self, why: String) {
        if let Some(form) = &mut self.form {
            form.error = Some(why);
        }
    }

    /// `choice` remembered for its server, as changed while the session runs (a goal moved).
    pub(in crate::app::state) fn remember(&mut self, choice: LiveChoice) {
        self.remembered.insert(choice.url.clone(), choice);
    }

    /// A session starts with `choice`: the form closes and the choice is remembered for its server.
    pub(in crate::app::state) fn start(
        &mut self,
        choice: LiveChoice,
        recording: RecordingId,
        drive: Option<LiveDrive>,
    ) -> WorkerLink {
        self.stop();
        self.form = None;
        self.remembered.insert(choice.url.clone(), choice.clone());
        self.last_url = Some(choice.url.clone());
        let link = WorkerLink::default();
        self.session = Some(Running {
            choice,
            link: link.clone(),
            latest: Latest::default(),
            gaps: Vec::new(),
            frames: 0,
            recording,
            images: BTreeMap::new(),
            said_connected: false,
            said_end: false,
            drive,
        });
        link
    }

    /// Asks the worker to end the session (it closes the recording and says what it holds).
    pub(in crate::app::state) fn stop(&mut self) {
        if let Some(running) = &self.session {
            running.link.stop();
        }
    }

    /// Empties the inbox: the frames that came, and the sentences to say; the rest is kept as the
    /// latest.
    pub(in crate::app::state) fn take(&mut self) -> Option<(Vec<Frame>, Vec<String>)> {
        let running = self.session.as_mut()?;
        let (handed, latest) =
            (running.link).with(|inbox| (std::mem::take(&mut inbox.handed), inbox.latest.clone()));
        running.latest = latest;
        running.gaps.extend(handed.gaps);
        running.images.extend(handed.images);
        running.frames += handed.frames.len();
        Some((handed.frames, handed.said))
    }
}

impl Drop for Live {
    /// A session's worker ends with the app: the recording closed cleanly.
    fn drop(&mut self) {
        self.stop();
    }
}

/// What a page says when asked to reach a robot's server: a browser tab has no plain sockets, and the
/// page does not speak the Foxglove protocol over the browser's WebSocket yet (the desktop's client
/// is `tungstenite`'s). One sentence, wherever a page is asked (the form's topics, Connect).
pub const NOT_IN_A_PAGE: &str = "a browser tab cannot connect to a robot's server yet: use the desktop app, or pushlab live ws://… in a terminal";

#[cfg(not(target_arch = "wasm32"))]
fn list(url: &str, stop: &dyn Fn() -> bool) -> Listed {
    pushlab_core::live::list_topics(url, LISTEN, stop).map_err(|e| e.to_string())
}

#[cfg(target_arch = "wasm32")]
fn list(_: &str, _: &dyn Fn() -> bool) -> Listed {
    Err(NOT_IN_A_PAGE.to_owned())
}

/// `path`, or when a file is there already, the first of `NAME-2.EXT`, `NAME-3.EXT`… that is not:
/// a recording is never written over, and the form should not make the user think of a new name
/// each time.
pub fn next_free(path: &Path) -> PathBuf {
    if path.as_os_str().is_empty() || !path.exists() {
        return path.to_path_buf();
    }
    let stem = path.file_stem().map_or_else(String::new, |s| {
        let s = s.to_string_lossy();
        // `push-3` goes on as `push-4`, not `push-3-2`.
        match s.rsplit_once('-') {
            Some((base, n)) if n.parse::<u32>().is_ok() => base.to_owned(),
            _ => s.into_owned(),
        }
    });
    let ext = path
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    (2..)
        .map(|n| path.with_file_name(format!("{stem}-{n}{ext}")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| path.to_path_buf())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn the_form_opens_with_the_last_servers_choice_and_a_recording_name_not_taken() {
        let dir = std::env::temp_dir().join(format!("pushlab-live-form-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("push.mcap"), b"taken").unwrap();
        std::fs::write(dir.join("push-2.mcap"), b"taken").unwrap();
        let robot = LiveChoice {
            url: "ws://robot:8765".to_owned(),
            pusher: "/tf:pusher".to_owned(),
            object: "/box".to_owned(),
            setting: dir.join("setting.json"),
            record: dir.join("push.mcap"),
            rate_hz: Some(100.0),
            drive: Box::default(),
        };
        let mut live = Live::new(
            BTreeMap::from([(robot.url.clone(), robot.clone())]),
            Some(robot.url.clone()),
        );
        live.apply_form(&LiveCommand::OpenForm);
        let form = live.form().unwrap().clone();
        assert_eq!(form.choice.pusher, "/tf:pusher");
        assert_eq!(form.choice.record, dir.join("push-3.mcap"));

        // Typing another server's address that was used before brings its choice back.
        let other = LiveChoice {
            url: "ws://sim:9000".to_owned(),
            pusher: "/pusher".to_owned(),
            ..LiveChoice::default()
        };
        live.remembered.insert(other.url.clone(), other.clone());
        live.apply_form(&LiveCommand::Edit(LiveChoice {
            url: "ws://sim:9000".to_owned(),
            ..form.choice.clone()
        }));
        assert_eq!(live.form().unwrap().choice.pusher, "/pusher");
        // An address no one connected to keeps what was typed.
        let typed = LiveChoice {
            url: "ws://new:1".to_owned(),
            pusher: "/p".to_owned(),
            ..LiveChoice::default()
        };
        live.apply_form(&LiveCommand::Edit(typed.clone()));
        assert_eq!(live.form().unwrap().choice, typed);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
