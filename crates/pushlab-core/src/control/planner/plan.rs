//! What a control step decides, for the pusher and for whoever draws or logs it.

use nalgebra::Point2;

use crate::control::sites::Site;
use crate::geometry::Pose2;

/// What the controller is doing this step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The pusher pushes (or closes the last centimetres to the object along the push).
    Pushing,
    /// The pusher goes to where its next push starts, round the object.
    Moving,
    /// The object is at the goal: the pusher holds still.
    Holding,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Pushing => "pushing",
            Phase::Moving => "moving",
            Phase::Holding => "holding",
        }
    }
}

/// The push chosen: where, which way, how far, and what it was judged to give.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChosenPush {
    pub site: Site,
    /// Radians from the inward normal, counter-clockwise positive.
    pub angle: f64,
    /// Metres of pushing planned: to the arc's nearest point to the goal, or where the push
    /// after it takes over.
    pub length_m: f64,
    /// The planner's distance to the goal where the plan ends (after the push after it, if
    /// any; see [`crate::control::Goal::distance`]), metres.
    pub expected_distance_m: f64,
    /// Metres of the pusher's way to the push's start.
    pub way_m: f64,
    /// The push planned after it, if going on from it was worth more than stopping there.
    pub then: Option<SecondPush>,
}

/// The push a plan goes on with ([`super::lookahead`]): replanned when the pusher gets there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SecondPush {
    pub site: Site,
    /// Radians from the inward normal.
    pub angle: f64,
    pub length_m: f64,
}

/// One control step's decision, for the pusher and for whoever draws or logs it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Plan {
    pub phase: Option<Phase>,
    /// Where the pusher should be at the end of this step, world frame.
    pub target: Point2<f64>,
    pub push: Option<ChosenPush>,
    /// The object's predicted poses along the chosen push (world), from now to its end.
    pub predicted: Vec<Pose2>,
    /// The object's predicted poses along the push planned after it (world), from where the
    /// first ends; empty if none.
    pub then: Vec<Pose2>,
    /// The pusher's way to the push's start (world), when moving.
    pub way: Vec<Point2<f64>>,
    /// Model predictions made this step.
    pub predictions: usize,
}
