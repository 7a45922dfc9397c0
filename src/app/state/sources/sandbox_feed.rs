//! The sandbox in the whole state: its pushes open as recordings of one set, each grown frame by
//! frame on the path every growing push takes (`grow`) and learned as it grows, going on from what
//! the push before it learned (as `pushlab eval --carry-theta` goes on from push to push, so the
//! saved session evaluates to the θ shown); each push reviewed against the ranking's choice when
//! it ends; the guess, the reveal and its score card; the session saved as a recording set.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::{Point2, Vector2};
use pushlab_core::recording::{Recording, RecordingSet};
use pushlab_core::sandbox::mystery::SANDBOX_NOISE;
use pushlab_core::sandbox::{
    Hidden, Mystery, MysteryObject, PointerPath, Sandbox, SandboxEvent, SandboxSet, ScoreCard,
    Scored, review_push,
};
use pushlab_core::trajectory::{Frame, Trajectory};

use crate::app::platform::Instant;
use crate::app::state::learning::online::Carried;
use crate::app::state::recordings::session::RecordingId;
use crate::app::state::sources::growing::Feed;
use crate::app::state::sources::sandbox::{STEER_REACH_M, SandboxCommand, SandboxSession};
use crate::app::state::{AppState, SessionCommand};

impl AppState {
    pub(in crate::app::state) fn apply_sandbox(&mut self, command: SandboxCommand) {
        match command {
            SandboxCommand::Start {
                seed,
                object,
                noise,
                challenge,
                com,
            } => self.start_sandbox(seed, object, noise, challenge, com),
            SandboxCommand::NewMystery => {
                if let Some(s) = &self.sandbox {
                    let (seed, object) =
                        (s.sandbox.mystery().seed, s.sandbox.mystery().object.clone());
                    let (noise, challenge) = (s.noise, s.challenge);
                    self.start_sandbox(seed.wrapping_add(1), Some(object), noise, challenge, None);
                }
            }
            SandboxCommand::Hold([x, y]) => {
                if let Some(s) = &mut self.sandbox {
                    s.steering = false;
                    let events = s.sandbox.hold(Point2::new(x, y));
                    self.take_sandbox_events(events);
                }
            }
            SandboxCommand::Release([x, y]) => {
                if let Some(s) = &mut self.sandbox {
                    s.sandbox.release(Point2::new(x, y));
                }
            }
            SandboxCommand::Steer(direction) => self.steer_sandbox(direction),
            SandboxCommand::Drag(points) => self.drag_sandbox(&points),
            SandboxCommand::Push(choice) => {
                let Some(s) = &mut self.sandbox else { return };
                match s.sandbox.plan(choice) {
                    Ok(events) => self.take_sandbox_events(events),
                    Err(why) => self.status = Some(format!("that push cannot be made: {why}")),
                }
            }
            SandboxCommand::Guess(at) => {
                if let Some(s) = &mut self.sandbox {
                    s.guess = Some(at);
                }
            }
            SandboxCommand::Reveal => self.reveal_sandbox(),
            SandboxCommand::SetChallenge(on) => {
                if let Some(s) = &mut self.sandbox {
                    s.challenge = on;
                }
            }
            SandboxCommand::SetGoal(goal) => self.set_sandbox_goal(goal),
            SandboxCommand::SetPlanWith(with) => self.set_plan_with(with),
            SandboxCommand::PushToGoal => self.push_to_goal(),
            SandboxCommand::StopPushToGoal => self.stop_push_to_goal("stopped"),
            SandboxCommand::Close => self.sandbox = None,
        }
    }

    /// A new sandbox on the mystery of `seed` (the shown recording's outline when `object` is
    /// none); its pushes open as a set of their own.
    fn start_sandbox(
        &mut self,
        seed: u64,
        object: Option<MysteryObject>,
        noise: bool,
        challenge: bool,
        com: Option<[f64; 2]>,
    ) {
        let object = object.unwrap_or_else(|| match self.session.selected_recording() {
            Some(r) => MysteryObject::Outline {
                name: r.name.clone(),
                shape: r.setting.object.clone(),
                pusher_radius: r.setting.pusher_radius,
            },
            None => MysteryObject::Box,
        });
        let drawn = Mystery::draw(seed, object.clone()).and_then(|drawn| match com {
            Some(com_offset) => Mystery::with_hidden(
                seed,
                object,
                Hidden {
                    com_offset,
                    ..drawn.hidden
                },
            ),
            None => Ok(drawn),
        });
        let mystery = match drawn {
            Ok(mystery) => mystery,
            Err(why) => {
                self.status = Some(format!("no mystery on that object: {why}"));
                return;
            }
        };
        let name = mystery.object.name().to_owned();
        // The table is shown, not the recording that was: nothing selected until the first push.
        if self
            .growing
            .as_ref()
            .is_some_and(|g| g.feed == Feed::Sandbox)
        {
            self.close_growing();
        }
        self.session.selected = None;
        self.start_run();
        self.session.sets.push(RecordingSet {
            dir: PathBuf::from(format!("sandbox {seed} {name}")),
            setting: Arc::new(mystery.public_setting()),
            recordings: Vec::new(),
        });
        self.sandbox = Some(SandboxSession {
            sandbox: Sandbox::new(mystery, noise.then_some(SANDBOX_NOISE)),
            set: self.session.sets.len() - 1,
            pushes: Vec::new(),
            noise,
            teachers_com: com,
            guess: None,
            revealed: false,
            challenge,
            steering: false,
            reviews: Vec::new(),
            score: None,
            carried: Vec::new(),
            next_start: None,
            step_ms: None,
            longest_step_ms: 0.0,
            goal: None,
            plan_with: pushlab_core::control::PlanWith::Online,
            driving: None,
            last_drive: None,
        });
        self.status = Some(format!(
            "a mystery {name} (seed {seed}): drag the yellow pusher into it, or draw an arrow on \
             its outline; drag the ? to guess where its centre of mass is"
        ));
    }

    /// The arrow keys held: the pusher heads `STEER_REACH_M` beyond itself that way; none held,
    /// let go where it is.
    fn steer_sandbox(&mut self, [dx, dy]: [f64; 2]) {
        let Some(s) = &mut self.sandbox else { return };
        let direction = Vector2::new(dx, dy);
        let pusher = s.sandbox.pusher();
        if direction.norm() > 0.0 {
            s.steering = true;
            let events = s
                .sandbox
                .hold(pusher + direction.normalize() * STEER_REACH_M);
            self.take_sandbox_events(events);
        } else if s.steering {
            s.steering = false;
            s.sandbox.release(pusher);
        }
    }

    /// A whole pointer path at once: the push it makes, made and learned now.
    fn drag_sandbox(&mut self, points: &[[f64; 3]]) {
        let Some(s) = &mut self.sandbox else { return };
        let result = PointerPath::from_points(points)
            .map_err(|e| e.to_string())
            .and_then(|path| s.sandbox.drag(path).map_err(|e| e.to_string()));
        match result {
            Ok(events) => self.take_sandbox_events(events),
            Err(why) => self.status = Some(format!("that drag cannot be made: {why}")),
        }
    }

    /// Time passes for the sandbox: the frames its push makes meanwhile. Returns whether a push is
    /// being made (the app keeps drawing).
    pub(in crate::app::state) fn poll_sandbox(&mut self, dt: f64) -> bool {
        if self.sandbox.is_none() {
            return false;
        }
        let started = Instant::now();
        self.drive_sandbox();
        let Some(s) = &mut self.sandbox else {
            return false;
        };
        let events = s.sandbox.advance(dt);
        let made = !events.is_empty();
        self.take_sandbox_events(events);
        // The sandbox's own work this frame (simulate, grow, learn; a push's review at its end),
        // for the page's and the guide's figures.
        if made && let Some(s) = &mut self.sandbox {
            let ms = started.elapsed().as_secs_f64() * 1e3;
            s.step_ms = Some(ms);
            s.longest_step_ms = s.longest_step_ms.max(ms);
        }
        self.sandbox
            .as_ref()
            .is_some_and(|s| s.sandbox.is_pushing() || s.driving.is_some())
    }

    pub(in crate::app::state) fn take_sandbox_events(&mut self, events: Vec<SandboxEvent>) {
        for event in events {
            match event {
                SandboxEvent::PushStarted { push, first } => self.open_sandbox_push(push, first),
                SandboxEvent::Frames { frames, .. } => self.grow(frames),
                SandboxEvent::PushEnded { push } => self.end_sandbox_push(push),
            }
        }
    }

    /// A push began: its recording opens in the sandbox's set, is shown, and grows.
    fn open_sandbox_push(&mut self, push: usize, first: Frame) {
        let Some(s) = &mut self.sandbox else { return };
        let Some(set) = self.session.sets.get_mut(s.set) else {
            return;
        };
        let file = format!("push_{push:03}.csv");
        set.recordings.push(Recording {
            source: set.dir.join(&file),
            name: format!("push {push}"),
            setting: Arc::clone(&set.setting),
            entry: None,
            trajectory: Arc::new(Trajectory::new(vec![first])),
            warnings: Vec::new(),
            notes: Vec::new(),
            cameras: Vec::new(),
        });
        let id = RecordingId {
            set: s.set,
            recording: set.recordings.len() - 1,
        };
        s.pushes.push(id);
        // Learning goes on from where the push before ended.
        let start = s.next_start.take();
        s.carried.push(start);
        self.remember_parameters();
        self.apply_session(SessionCommand::Select(id));
        self.start_growing(id, Feed::Sandbox);
    }

    /// A push ended: it stops growing, is reviewed against the ranking's choice, and what it
    /// learned is kept for the next push to go on from.
    fn end_sandbox_push(&mut self, push: usize) {
        self.close_growing();
        let Some(s) = &self.sandbox else { return };
        let Some(&id) = s.pushes.get(push) else {
            return;
        };
        let shown = self.session.selected == Some(id);
        if shown {
            // Every sample learned, also those scrubbed back over before the push ended.
            let skip = self.frames_to_skip();
            if let Some(run) = &mut self.run {
                let (from, to) = (run.frontier(), run.sample_count());
                run.learn_through(from, to, &skip);
            }
        }
        let end = self.run.as_ref().filter(|_| shown).map(|run| Carried {
            from: format!("push {push}"),
            start: run.end_state(),
            beside: run.beside_end(),
        });
        let review = self.run.as_ref().filter(|_| shown).and_then(|run| {
            let recording = self.session.get(id)?;
            review_push(
                run.model().as_ref(),
                run.horizon(),
                run.start_state(),
                push,
                recording,
            )
            .ok()
        });
        if let Some(s) = &mut self.sandbox {
            s.reviews.resize(push + 1, None);
            s.reviews[push] = review;
            s.next_start = end;
        }
        // Measured again now that the push is whole (the browser's columns).
        if let Some(source) = self.session.get(id).map(|r| r.source.clone()) {
            self.browsed.forget_parameters(&source);
            self.remember_parameters();
        }
    }

    /// Shows the truth and the score card.
    fn reveal_sandbox(&mut self) {
        let Some(s) = &mut self.sandbox else { return };
        // What the last push finished with (not the push shown: the student may have gone back
        // to an earlier one); a push still being made, as far as it is learned.
        let end = (s.next_start.as_ref().map(|c| c.start))
            .or_else(|| self.run.as_ref().map(|run| run.end_state()));
        s.revealed = true;
        let mystery = s.sandbox.mystery();
        // The truth joins the pushes' setting: the true COM layer, the Steer tab's truth line.
        if let Some(set) = self.session.sets.get_mut(s.set) {
            set.setting = Arc::new(mystery.setting());
            for recording in &mut set.recordings {
                recording.setting = Arc::clone(&set.setting);
            }
        }
        let Some(end) = end else {
            self.status = Some("push the object first: the model has nothing to go on".into());
            return;
        };
        s.score = Some(ScoreCard::of(Scored {
            true_com_m: mystery.hidden.com_offset,
            true_h_m: mystery.h,
            guess_m: s.guess,
            end: &end,
            push_length_m: s.sandbox.made().iter().map(|m| m.pressed_length()).sum(),
            reviews: s.reviews.iter().flatten().cloned().collect(),
        }));
    }

    /// The carried state a sandbox push's run starts from, if `id` is one of its pushes after the
    /// first.
    pub(in crate::app::state) fn sandbox_carried_for(&self, id: RecordingId) -> Option<Carried> {
        let s = self.sandbox.as_ref()?;
        let push = s.pushes.iter().position(|p| *p == id)?;
        s.carried.get(push).cloned().flatten()
    }

    /// Writes the sandbox's finished pushes into `dir` as a recording set with the truth.
    pub(in crate::app::state) fn save_sandbox(&mut self, dir: &Path) {
        let Some(s) = &self.sandbox else {
            self.status = Some("no sandbox to save".into());
            return;
        };
        let recorded: Vec<Trajectory> = (s.pushes.iter().take(s.sandbox.made().len()))
            .filter_map(|id| self.session.get(*id).map(|r| (*r.trajectory).clone()))
            .collect();
        let set = SandboxSet::of(&s.sandbox, &recorded);
        self.status = Some(match set.write(dir) {
            Ok(()) => format!(
                "saved {} push(es) with the truth to {}",
                set.trajectories.len(),
                dir.display()
            ),
            Err(why) => format!("could not save the sandbox: {why}"),
        });
    }

    /// The sandbox, for the panels.
    pub fn sandbox(&self) -> Option<&SandboxSession> {
        self.sandbox.as_ref()
    }

    /// Whether the scene shows the sandbox's object: before its first push (nothing else shown),
    /// or one of its pushes.
    pub fn sandbox_shown(&self) -> bool {
        self.sandbox
            .as_ref()
            .is_some_and(|s| match self.session.selected {
                None => true,
                Some(id) => id.set == s.set,
            })
    }

    /// Whether the model's estimate is hidden in the scene and the tabs now (challenge mode on the
    /// sandbox shown, before the reveal).
    pub fn estimate_hidden(&self) -> bool {
        self.sandbox_shown()
            && self
                .sandbox
                .as_ref()
                .is_some_and(SandboxSession::hides_estimate)
    }
}
