//! Push it yourself: the sandbox's own state. The core's sandbox (the mystery object on the table
//! and the pushes made on it), the set its pushes open as (one recording a push), the student's
//! guess of the COM, whether the truth is revealed, challenge mode (the model's estimate hidden
//! until reveal), each push's review and the score card. The pushes grow on the path every growing
//! push takes (`sources::grow`, `sandbox_feed`).

use pushlab_core::control::PlanWith;
use pushlab_core::geometry::Pose2;
use pushlab_core::sandbox::{MysteryObject, PushChoice, PushReview, Sandbox, ScoreCard};

use crate::app::state::learning::online::Carried;
use crate::app::state::recordings::session::RecordingId;
pub use crate::app::state::sources::driving::Driving;

/// What the sandbox is asked.
#[derive(Clone, Debug, PartialEq)]
pub enum SandboxCommand {
    /// A new sandbox: the mystery of `seed` on `object` (`None`: the outline of the recording
    /// shown), tracking noise or not, the model's estimate hidden until reveal or not; `com`, a
    /// teacher's hidden COM offset (object frame, metres) in place of the seed's.
    Start {
        seed: u64,
        object: Option<MysteryObject>,
        noise: bool,
        challenge: bool,
        com: Option<[f64; 2]>,
    },
    /// The next mystery: the next seed, the same object.
    NewMystery,
    /// The pointer holds the pusher at this world point (pressed, or moved while pressed).
    Hold([f64; 2]),
    /// The pointer let go at this world point.
    Release([f64; 2]),
    /// The arrow keys held steer the pusher this way (world axes; zero: let go).
    Steer([f64; 2]),
    /// A whole pointer path at once (`[x, y, t]`, metres and seconds from now), as the page's hook
    /// and tests drag.
    Drag(Vec<[f64; 3]>),
    /// A push chosen on the object, made by the pusher as `pushlab simulate` plans one.
    Push(PushChoice),
    /// The student's guess of the COM offset, object frame, metres.
    Guess([f64; 2]),
    /// Show the hidden COM and `h`, and the score card.
    Reveal,
    /// Hide the model's estimate until reveal (or show it).
    SetChallenge(bool),
    /// Where the object should go: its centre `x, y` (metres) and yaw (radians), world frame.
    SetGoal([f64; 3]),
    /// What the controller plans with.
    SetPlanWith(PlanWith),
    /// The controller pushes the object to the goal (with the model as it learns, or as chosen).
    PushToGoal,
    /// The controller lets go where the pusher is.
    StopPushToGoal,
    /// Leave the sandbox (its pushes stay open).
    Close,
}

/// How far ahead of the pusher the arrow keys put the pointer, metres: the pusher heads there at
/// its speed while they are held.
pub const STEER_REACH_M: f64 = 0.05;

/// A sandbox session (see the module documentation).
pub struct SandboxSession {
    pub(in crate::app::state) sandbox: Sandbox,
    /// Its pushes' set among the open sets.
    pub(in crate::app::state) set: usize,
    /// Each push's recording, in order.
    pub(in crate::app::state) pushes: Vec<RecordingId>,
    pub(in crate::app::state) noise: bool,
    /// The hidden COM a teacher gave in place of the seed's, if one did (a link says it again).
    pub(in crate::app::state) teachers_com: Option<[f64; 2]>,
    pub(in crate::app::state) guess: Option<[f64; 2]>,
    pub(in crate::app::state) revealed: bool,
    pub(in crate::app::state) challenge: bool,
    /// Whether the arrow keys hold the pusher now.
    pub(in crate::app::state) steering: bool,
    /// Each push's review, once it ended (`None` where the ranking could not review it).
    pub(in crate::app::state) reviews: Vec<Option<PushReview>>,
    pub(in crate::app::state) score: Option<ScoreCard>,
    /// The learning each push started from (none for the first: `θ_online(0)`).
    pub(in crate::app::state) carried: Vec<Option<Carried>>,
    /// What the last push ended with, for the next to go on from.
    pub(in crate::app::state) next_start: Option<Carried>,
    /// The sandbox's own work on the UI thread in the last frame that made frames, and the
    /// longest such, ms.
    pub(in crate::app::state) step_ms: Option<f64>,
    pub(in crate::app::state) longest_step_ms: f64,
    /// Where the object should go (world frame), and what the controller plans with.
    pub(in crate::app::state) goal: Option<Pose2>,
    pub(in crate::app::state) plan_with: PlanWith,
    pub(in crate::app::state) driving: Option<Driving>,
    /// How the last push to the goal ended: reached, after how many seconds.
    pub(in crate::app::state) last_drive: Option<(bool, f64, PlanWith)>,
}

impl SandboxSession {
    pub fn sandbox(&self) -> &Sandbox {
        &self.sandbox
    }

    /// The recording of each push made or being made.
    pub fn pushes(&self) -> &[RecordingId] {
        &self.pushes
    }

    pub fn guess(&self) -> Option<[f64; 2]> {
        self.guess
    }

    pub fn revealed(&self) -> bool {
        self.revealed
    }

    pub fn challenge(&self) -> bool {
        self.challenge
    }

    pub fn noise(&self) -> bool {
        self.noise
    }

    /// The hidden COM a teacher gave in place of the seed's, if one did.
    pub fn teachers_com(&self) -> Option<[f64; 2]> {
        self.teachers_com
    }

    /// The score card, after reveal.
    pub fn score(&self) -> Option<&ScoreCard> {
        self.score.as_ref()
    }

    /// Each push's review, in order, once it ended.
    pub fn reviews(&self) -> &[Option<PushReview>] {
        &self.reviews
    }

    /// Whether the arrow keys hold the pusher now.
    pub fn steering(&self) -> bool {
        self.steering
    }

    /// The sandbox's own work on the UI thread (simulate, grow, learn, a push's review) in the last
    /// frame that made frames, and the longest such since it opened, ms.
    pub fn step_ms(&self) -> (Option<f64>, f64) {
        (self.step_ms, self.longest_step_ms)
    }

    /// Where the object should go, world frame.
    pub fn goal(&self) -> Option<Pose2> {
        self.goal
    }

    pub fn plan_with(&self) -> PlanWith {
        self.plan_with
    }

    /// The controller, while it pushes.
    pub fn driving(&self) -> Option<&Driving> {
        self.driving.as_ref()
    }

    /// How the last push to the goal ended: reached or stopped, after how many seconds, planned
    /// with what.
    pub fn last_drive(&self) -> Option<(bool, f64, PlanWith)> {
        self.last_drive
    }

    /// Whether the model's estimate is hidden now (challenge mode, before reveal).
    pub fn hides_estimate(&self) -> bool {
        self.challenge && !self.revealed
    }
}
