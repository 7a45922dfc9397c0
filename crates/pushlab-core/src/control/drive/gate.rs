//! The safety gate between the controller and a robot: every target the controller plans passes
//! through it, and only what it lets out is sent. Its rules, each a test below that fails without
//! it:
//!
//! - nothing is sent until the user arms it;
//! - a target is kept inside the workspace box, then no further from the pusher than one control
//!   step at the top speed (the step bound last, so that it holds even when the pusher is outside
//!   the box and the box's nearest point is far);
//! - when either pose stream goes stale (no pose received for [`STALE_AFTER`]), on pause, disarm,
//!   the user's interrupt (Ctrl-C), the goal reached or the link lost, the pusher's own position is
//!   sent once (hold) and then nothing more until the user arms it again.
//!
//! Pure, with the time passed in, as the app's timeline is: no clock and no socket here, so each
//! rule is tested to the step.

use std::time::Duration;

use nalgebra::Point2;

/// How old the newest pose of either stream may be before the gate holds the pusher.
pub const STALE_AFTER: Duration = Duration::from_millis(200);

/// A rectangle of the pose streams' frame the pusher's target is kept in, metres.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Workspace {
    pub min: [f64; 2],
    pub max: [f64; 2],
}

impl Workspace {
    /// The box from `X0,Y0,X1,Y1` corners in any order; refused unless it has an area.
    pub fn new(a: Point2<f64>, b: Point2<f64>) -> Result<Self, String> {
        let min = [a.x.min(b.x), a.y.min(b.y)];
        let max = [a.x.max(b.x), a.y.max(b.y)];
        let finite = [a.x, a.y, b.x, b.y].iter().all(|v| v.is_finite());
        if !finite || min[0] >= max[0] || min[1] >= max[1] {
            return Err(format!(
                "a workspace from ({}, {}) to ({}, {}) has no area: expected two opposite corners",
                a.x, a.y, b.x, b.y
            ));
        }
        Ok(Self { min, max })
    }

    /// The box around the points, widened by `margin` on every side.
    pub fn around(points: &[Point2<f64>], margin: f64) -> Self {
        let mut min = [f64::INFINITY; 2];
        let mut max = [f64::NEG_INFINITY; 2];
        for p in points {
            min = [min[0].min(p.x), min[1].min(p.y)];
            max = [max[0].max(p.x), max[1].max(p.y)];
        }
        Self {
            min: [min[0] - margin, min[1] - margin],
            max: [max[0] + margin, max[1] + margin],
        }
    }

    /// Whether an object reaching `reach` from its centre at `centre` lies inside the box, turned
    /// any way: where a goal may be moved to once the box is taken (the pusher is kept in it).
    pub fn fits(&self, centre: Point2<f64>, reach: f64) -> bool {
        (0..2).all(|i| {
            let c = centre[i];
            c.is_finite() && c - reach >= self.min[i] && c + reach <= self.max[i]
        })
    }

    fn clamp(&self, p: Point2<f64>) -> Point2<f64> {
        Point2::new(
            p.x.clamp(self.min[0], self.max[0]),
            p.y.clamp(self.min[1], self.max[1]),
        )
    }
}

/// What bounds a target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// The pusher's top speed, m/s.
    pub speed: f64,
    /// Control steps a second: a target is at most `speed / control_hz` from the pusher.
    pub control_hz: f64,
    pub workspace: Workspace,
}

/// Why the gate stopped sending.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Halt {
    /// No pose of a stream for longer than [`STALE_AFTER`].
    Stale,
    /// No new target from the planner for a grid frame past [`STALE_AFTER`] (a planner on another
    /// thread stopped: the app's window frozen).
    PlanStale,
    Paused,
    Disarmed,
    /// The user's interrupt (Ctrl-C).
    Interrupted,
    /// The goal is reached and held.
    Reached,
    /// The connection to the robot's server dropped.
    LinkLost,
    /// The run's time limit passed before the goal was reached.
    TimeLimit,
}

impl Halt {
    /// In words, for a status line.
    pub fn describe(self) -> &'static str {
        match self {
            Halt::Stale => "the poses went stale (none for 200 ms)",
            Halt::PlanStale => "the plan went stale (no new target for a grid frame and 200 ms)",
            Halt::Paused => "paused",
            Halt::Disarmed => "disarmed",
            Halt::Interrupted => "interrupted (Ctrl-C)",
            Halt::Reached => "the goal is reached and held",
            Halt::LinkLost => "the link to the robot's server dropped",
            Halt::TimeLimit => "the time limit passed",
        }
    }
}

/// What the gate lets out: a bounded target, or the pusher's own position once on a halt.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Command {
    Move { target: [f64; 2] },
    Hold { at: [f64; 2] },
}

impl Command {
    pub fn point(&self) -> Point2<f64> {
        let (Command::Move { target: p } | Command::Hold { at: p }) = self;
        Point2::new(p[0], p[1])
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// Never armed, or armed again after a halt was said: nothing to send.
    Disarmed,
    Armed,
    Halted(Halt),
}

/// The gate (see the module documentation).
#[derive(Clone, Debug)]
pub struct SafetyGate {
    limits: Limits,
    state: State,
}

impl SafetyGate {
    /// A gate that sends nothing until armed.
    pub fn new(limits: Limits) -> Self {
        Self {
            limits,
            state: State::Disarmed,
        }
    }

    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    pub fn is_armed(&self) -> bool {
        self.state == State::Armed
    }

    /// Why the gate stopped sending, if it did since it was last armed.
    pub fn halted(&self) -> Option<Halt> {
        match self.state {
            State::Halted(h) => Some(h),
            _ => None,
        }
    }

    /// The user arms it: targets are sent from the next control step on.
    pub fn arm(&mut self) {
        self.state = State::Armed;
    }

    /// Stops sending for `why`: the hold to send once, at `pusher` (the pusher's newest
    /// position), if the gate was armed; nothing if it was not (nothing was moving the robot).
    pub fn halt(&mut self, why: Halt, pusher: Option<Point2<f64>>) -> Option<Command> {
        match self.state {
            State::Armed => {
                self.state = State::Halted(why);
                pusher.map(|p| Command::Hold { at: [p.x, p.y] })
            }
            State::Disarmed | State::Halted(_) => None,
        }
    }

    /// A control step: what to send for the controller's `planned` target, the pusher at
    /// `pusher`, its newest pose received `pusher_age` ago and the object's `object_age` ago.
    pub fn command(
        &mut self,
        planned: Point2<f64>,
        pusher: Point2<f64>,
        pusher_age: Duration,
        object_age: Duration,
    ) -> Option<Command> {
        if self.state != State::Armed {
            return None;
        }
        if pusher_age > STALE_AFTER || object_age > STALE_AFTER {
            return self.halt(Halt::Stale, Some(pusher));
        }
        let inside = self.limits.workspace.clamp(planned);
        let step = self.limits.speed / self.limits.control_hz;
        let offset = inside - pusher;
        let target = match offset.norm() > step {
            true => pusher + offset * (step / offset.norm()),
            false => inside,
        };
        Some(Command::Move {
            target: [target.x, target.y],
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    const FRESH: Duration = Duration::from_millis(20);

    fn gate() -> SafetyGate {
        SafetyGate::new(Limits {
            speed: 0.04,
            control_hz: 10.0,
            workspace: Workspace::new(Point2::new(-0.5, -0.5), Point2::new(0.5, 0.5)).unwrap(),
        })
    }

    fn armed() -> SafetyGate {
        let mut g = gate();
        g.arm();
        g
    }

    fn at(x: f64, y: f64) -> Point2<f64> {
        Point2::new(x, y)
    }

    #[test]
    fn nothing_is_sent_before_the_user_arms_it() {
        let mut g = gate();
        for _ in 0..3 {
            assert_eq!(g.command(at(0.002, 0.0), at(0.0, 0.0), FRESH, FRESH), None);
        }
        assert_eq!(
            g.halt(Halt::Interrupted, Some(at(0.0, 0.0))),
            None,
            "no hold either"
        );
        g.arm();
        assert_eq!(
            g.command(at(0.002, 0.0), at(0.0, 0.0), FRESH, FRESH),
            Some(Command::Move {
                target: [0.002, 0.0]
            })
        );
    }

    #[test]
    fn a_target_is_no_further_than_a_step_at_the_top_speed() {
        let mut g = armed();
        let sent = g.command(at(0.3, 0.4), at(0.0, 0.0), FRESH, FRESH).unwrap();
        let step = sent.point() - at(0.0, 0.0);
        assert!((step.norm() - 0.004).abs() < 1e-12, "{}", step.norm());
        assert!(
            (step.y / step.x - 0.4 / 0.3).abs() < 1e-9,
            "along the way planned"
        );
    }

    #[test]
    fn a_target_is_kept_in_the_workspace() {
        let mut g = armed();
        // The pusher at the box's edge, the controller asking for a step out of it.
        let sent = g
            .command(at(0.503, 0.1), at(0.499, 0.1), FRESH, FRESH)
            .unwrap();
        assert_eq!(sent.point(), at(0.5, 0.1));
        // From outside (the robot put there by hand), it comes back in by steps.
        let sent = g.command(at(0.9, 0.1), at(0.8, 0.1), FRESH, FRESH).unwrap();
        assert!((sent.point() - at(0.796, 0.1)).norm() < 1e-12, "{sent:?}");
    }

    #[test]
    fn stale_poses_send_one_hold_then_nothing() {
        for (pusher_age, object_age) in [
            (Duration::from_millis(201), FRESH),
            (FRESH, Duration::from_millis(250)),
        ] {
            let mut g = armed();
            let hold = g.command(at(0.1, 0.0), at(0.05, 0.02), pusher_age, object_age);
            assert_eq!(hold, Some(Command::Hold { at: [0.05, 0.02] }));
            assert_eq!(g.halted(), Some(Halt::Stale));
            // Fresh again, still nothing until armed again.
            assert_eq!(g.command(at(0.1, 0.0), at(0.05, 0.02), FRESH, FRESH), None);
        }
        let mut g = armed();
        assert!(
            matches!(
                g.command(at(0.1, 0.0), at(0.0, 0.0), STALE_AFTER, STALE_AFTER),
                Some(Command::Move { .. })
            ),
            "200 ms exactly is not stale yet"
        );
    }

    #[test]
    fn every_halt_sends_one_hold_and_stops() {
        for why in [
            Halt::Paused,
            Halt::Disarmed,
            Halt::Interrupted,
            Halt::Reached,
            Halt::LinkLost,
            Halt::TimeLimit,
        ] {
            let mut g = armed();
            assert!(
                g.command(at(0.1, 0.0), at(0.0, 0.0), FRESH, FRESH)
                    .is_some()
            );
            assert_eq!(
                g.halt(why, Some(at(0.003, 0.0))),
                Some(Command::Hold { at: [0.003, 0.0] }),
                "{why:?}"
            );
            assert_eq!(g.halted(), Some(why));
            assert_eq!(
                g.halt(why, Some(at(0.003, 0.0))),
                None,
                "{why:?}: the hold is sent once"
            );
            assert_eq!(
                g.command(at(0.1, 0.0), at(0.003, 0.0), FRESH, FRESH),
                None,
                "{why:?}"
            );
            g.arm();
            assert!(
                g.command(at(0.1, 0.0), at(0.003, 0.0), FRESH, FRESH)
                    .is_some(),
                "{why:?}: armed again"
            );
        }
    }

    #[test]
    fn a_workspace_needs_an_area() {
        let why = Workspace::new(at(0.0, 0.0), at(0.0, 1.0)).expect_err("a line");
        assert!(why.contains("has no area"), "{why}");
        let w = Workspace::new(at(1.0, 1.0), at(-1.0, 0.0)).unwrap();
        assert_eq!((w.min, w.max), ([-1.0, 0.0], [1.0, 1.0]));
        assert!(Workspace::new(at(f64::NAN, 0.0), at(1.0, 1.0)).is_err());
    }

    #[test]
    fn an_object_fits_the_box_only_with_its_whole_reach_inside() {
        let w = Workspace::new(Point2::new(-0.5, -0.2), Point2::new(0.5, 0.4)).unwrap();
        assert!(w.fits(Point2::new(0.0, 0.1), 0.25));
        assert!(w.fits(Point2::new(0.25, 0.15), 0.25), "touching two sides");
        assert!(!w.fits(Point2::new(0.3, 0.1), 0.25), "past x's end");
        assert!(!w.fits(Point2::new(0.0, -0.1), 0.25), "past y's start");
        assert!(!w.fits(Point2::new(f64::NAN, 0.1), 0.25));
    }
}
