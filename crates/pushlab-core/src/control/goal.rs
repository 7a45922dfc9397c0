//! Where the object should end up and when it is there: a pose in the pose streams' frame, within
//! a position and a yaw tolerance (10 mm and 3° unless said), held still for a while.

use crate::geometry::{Pose2, wrap_angle};
use crate::math;

/// Within 10 mm unless told.
pub const DEFAULT_POSITION_TOLERANCE_M: f64 = 0.010;
/// Within 3° unless told.
pub const DEFAULT_YAW_TOLERANCE_RAD: f64 = 3.0 * std::f64::consts::PI / 180.0;
/// Control steps the object must stay within tolerance with the pusher holding, to count as
/// stopped there (half a second at 10 Hz).
pub const DEFAULT_HOLD_STEPS: usize = 5;

/// A goal pose and how close is close enough.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Goal {
    pub pose: Pose2,
    pub position_tolerance_m: f64,
    pub yaw_tolerance_rad: f64,
}

/// How far an object is from its goal.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GoalError {
    /// Distance between the object's centre and the goal's, metres.
    pub position_m: f64,
    /// The goal's yaw minus the object's, wrapped to (−π, π].
    pub yaw_rad: f64,
}

impl Goal {
    /// A goal at `pose` with the default tolerances.
    pub fn at(pose: Pose2) -> Self {
        Self {
            pose,
            position_tolerance_m: DEFAULT_POSITION_TOLERANCE_M,
            yaw_tolerance_rad: DEFAULT_YAW_TOLERANCE_RAD,
        }
    }

    /// How far `pose` is from the goal.
    pub fn error(&self, pose: &Pose2) -> GoalError {
        GoalError {
            position_m: (self.pose.position - pose.position).norm(),
            yaw_rad: wrap_angle(self.pose.yaw - pose.yaw),
        }
    }

    /// Whether `pose` is within both tolerances.
    pub fn is_within(&self, pose: &Pose2) -> bool {
        let e = self.error(pose);
        e.position_m <= self.position_tolerance_m && e.yaw_rad.abs() <= self.yaw_tolerance_rad
    }

    /// The planner's distance to the goal, metres: the position error plus the yaw error weighed so
    /// that one yaw tolerance counts as much as one position tolerance.
    pub fn distance(&self, pose: &Pose2) -> f64 {
        let e = self.error(pose);
        e.position_m + self.metres_per_radian() * e.yaw_rad.abs()
    }

    /// What a radian of yaw error is worth in metres of position error.
    pub fn metres_per_radian(&self) -> f64 {
        self.position_tolerance_m / self.yaw_tolerance_rad.max(1e-6)
    }
}

/// The goal of the measured pair `seed` (the bench's, its tests' and the sandbox mystery of that
/// seed): from the origin, 20–40 cm away, turned up to ±45°.
pub fn pair_goal(seed: u64) -> Pose2 {
    draw_goal(
        &Pose2::new(0.0, 0.0, 0.0),
        seed,
        (0.2, 0.4),
        std::f64::consts::FRAC_PI_4,
    )
}

/// A goal drawn for a measured pair: `distance_m` uniform in the range given, in any direction
/// from `start`, its yaw within ±`max_turn_rad` of the start's (the 20–40 cm and ±45°).
pub fn draw_goal(start: &Pose2, seed: u64, distance_m: (f64, f64), max_turn_rad: f64) -> Pose2 {
    let mut rng = crate::rng::SplitMix64::new(seed ^ 0x60A1_60A1);
    let distance = distance_m.0 + (distance_m.1 - distance_m.0) * rng.uniform();
    let direction = std::f64::consts::TAU * rng.uniform();
    let turn = max_turn_rad * (2.0 * rng.uniform() - 1.0);
    Pose2::new(
        start.position.x + distance * math::cos(direction),
        start.position.y + distance * math::sin(direction),
        start.yaw + turn,
    )
}
