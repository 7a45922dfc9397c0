//! A live session in the whole state: Connect opens a recording that grows as the worker's frames
//! arrive (`live`), on the one path a growing push takes (`grow`): learned online as they come by
//! the run every recording is learned with — the core's `OnlineRun`, so the session and a replay of
//! its recording give the same θ — with the timeline following the newest frame until the user
//! scrubs back ("Back to live" returns).

use std::path::PathBuf;
use std::sync::Arc;

use pushlab_core::recording::bag::SettingSource;
use pushlab_core::recording::{Recording, RecordingSet};
use pushlab_core::trajectory::Trajectory;

use crate::app::state::AppState;
use crate::app::state::recordings::session::RecordingId;
use crate::app::state::sources::growing::Feed;
use crate::app::state::sources::live::{Link, LiveCommand};

impl AppState {
    pub(in crate::app::state) fn apply_live(&mut self, command: &LiveCommand) {
        self.live.apply_form(command);
        match command {
            LiveCommand::Connect => self.connect_live(),
            LiveCommand::Disconnect => {
                if self.live.is_live() {
                    self.live.stop();
                    self.status = Some("ending the live session…".to_owned());
                }
            }
            LiveCommand::BackToLive => self.back_to_newest(),
            LiveCommand::Drive(command) => self.apply_drive(*command),
            LiveCommand::OpenForm
            | LiveCommand::Edit(_)
            | LiveCommand::CloseForm
            | LiveCommand::ListTopics => {}
        }
    }

    /// Starts a session with the form's choice, or says on the form why it cannot.
    fn connect_live(&mut self) {
        let Some(choice) = self.live.form_choice() else {
            return;
        };
        if cfg!(target_arch = "wasm32") {
            self.live.refuse(super::live::NOT_IN_A_PAGE.to_owned());
            return;
        }
        let checked = (|| {
            if !choice.url.starts_with("ws://") {
                return Err(format!(
                    "{}: the server's address is ws://HOST:PORT",
                    choice.url
                ));
            }
            if choice.pusher.trim().is_empty() || choice.object.trim().is_empty() {
                return Err("name the pusher's and the object's topics".to_owned());
            }
            if !choice.record.as_os_str().is_empty() && choice.record.exists() {
                return Err(format!(
                    "{}: already exists; pushlab does not write over a recording (choose a new name)",
                    choice.record.display()
                ));
            }
            let setting = SettingSource::File(choice.setting.clone())
                .resolve()
                .map_err(|e| e.to_string())?;
            let rate = match choice.rate_hz {
                Some(rate) if rate.is_finite() && rate > 0.0 => rate,
                Some(rate) => return Err(format!("the grid's rate {rate} Hz is not positive")),
                None => (self.models.training.domain.as_ref())
                    .and_then(|d| d.single_rate_hz())
                    .ok_or_else(|| {
                        "the model in use does not say the one frame rate it was trained at: enter the grid's rate".to_owned()
                    })?,
            };
            let drive = match choice.drive.on {
                true => Some(super::live_drive::prepare(
                    &choice.drive,
                    &setting,
                    self.models.combined.as_ref(),
                    rate,
                    self.run_generation,
                )?),
                false => None,
            };
            Ok((setting, rate, drive))
        })();
        let (setting, rate, drive) = match checked {
            Ok(ok) => ok,
            Err(why) => return self.live.refuse(why),
        };
        let (drive, setup) = drive.unzip();
        // The push is named after its recording, which is where it can be opened again later.
        let source = if choice.record.as_os_str().is_empty() {
            PathBuf::from(format!("live {}", choice.url))
        } else {
            choice.record.clone()
        };
        let name = source
            .file_stem()
            .map_or_else(|| "live".to_owned(), |s| s.to_string_lossy().into_owned());
        let setting = Arc::new(setting);
        let recording = Recording {
            source: source.clone(),
            name,
            setting: Arc::clone(&setting),
            entry: None,
            trajectory: Arc::new(Trajectory::new(Vec::new())),
            warnings: Vec::new(),
            notes: Vec::new(),
            cameras: Vec::new(),
        };
        self.session.sets.push(RecordingSet {
            dir: source.parent().map(PathBuf::from).unwrap_or_default(),
            setting,
            recordings: vec![recording],
        });
        let id = RecordingId {
            set: self.session.sets.len() - 1,
            recording: 0,
        };
        let url = choice.url.clone();
        let link = self.live.start(choice.clone(), id, drive);
        self.start_growing(id, Feed::Live);
        self.start_live_worker(choice, rate, setup, link);
        self.remember_parameters();
        self.apply_session(crate::app::state::SessionCommand::Select(id));
        self.status = Some(format!("connecting to {url}…"));
    }

    #[cfg(not(target_arch = "wasm32"))]
    fn start_live_worker(
        &self,
        choice: crate::app::state::sources::live::LiveChoice,
        rate: f64,
        drive: Option<super::live_drive::DriveSetup>,
        link: crate::app::state::sources::live::WorkerLink,
    ) {
        crate::app::platform::spawn(move || {
            crate::app::state::sources::live::worker::run(&choice, rate, drive.as_ref(), &link)
        });
    }

    #[cfg(target_arch = "wasm32")]
    fn start_live_worker(
        &self,
        _: crate::app::state::sources::live::LiveChoice,
        _: f64,
        _: Option<super::live_drive::DriveSetup>,
        _: crate::app::state::sources::live::WorkerLink,
    ) {
    }

    /// Takes what the worker handed over: the frames onto the push, what it said onto the status
    /// line. Returns whether a session is running (the app keeps drawing).
    pub(in crate::app::state) fn poll_live(&mut self) -> bool {
        self.live.poll_listing();
        let listing = self.live.is_listing();
        let Some((frames, said)) = self.live.take() else {
            return listing;
        };
        if let Some(last) = said.into_iter().last() {
            self.status = Some(last);
        }
        if let Some(running) = self.live.running_mut()
            && let Link::Connected { server } = &running.latest.link
            && !running.said_connected
        {
            running.said_connected = true;
            let record = &running.choice.record;
            self.status = Some(format!(
                "connected to {} ({server}): learning as the robot pushes{}",
                running.choice.url,
                if record.as_os_str().is_empty() {
                    String::new()
                } else {
                    format!(", recording every message to {}", record.display())
                }
            ));
        }
        if !frames.is_empty() {
            self.grow(frames);
            self.drive_live();
        }
        let mut ended = None;
        if let Some(running) = self.live.running_mut()
            && let Link::Ended { error, recorded } = &running.latest.link
            && !running.said_end
        {
            running.said_end = true;
            ended = Some(running.recording);
            self.status = Some(match (error, recorded) {
                (Some(error), _) => format!("the live session ended: {error}"),
                (None, Some(recorded)) => format!("the live session ended; {recorded}"),
                (None, None) => "the live session ended".to_owned(),
            });
            // The push is whole now: what was measured of it while it grew is measured again.
            let id = running.recording;
            if let Some(source) = self.session.get(id).map(|r| r.source.clone()) {
                self.browsed.forget_parameters(&source);
                self.remember_parameters();
            }
            if self.session.selected == Some(id) {
                (self.proposals).refresh(self.session.selected_recording(), self.run.as_ref());
            }
        }
        if let Some(id) = ended
            && self.growing.as_ref().is_some_and(|g| g.recording == id)
        {
            self.close_growing();
        }
        self.live.is_live() || listing
    }

    /// The newest picture of each camera of the live push shown, with the pictures each dropped
    /// from the display (they came faster than the window took them; the recording has them).
    pub fn live_images(&self) -> Option<crate::app::state::sources::live::LiveImages<'_>> {
        let running = self.live.running()?;
        (self.session.selected == Some(running.recording) && !running.images.is_empty())
            .then_some((&running.images, &running.latest.images_dropped))
    }

    /// Where the live push shown lost its connection (running or ended): the timeline marks them.
    pub fn live_gaps(&self) -> &[crate::app::state::sources::live::Gap] {
        (self.live.running())
            .filter(|r| self.session.selected == Some(r.recording))
            .map_or(&[], |r| &r.gaps)
    }

    /// The form and the session, for the panels.
    pub fn live(&self) -> &crate::app::state::sources::live::Live {
        &self.live
    }
}
