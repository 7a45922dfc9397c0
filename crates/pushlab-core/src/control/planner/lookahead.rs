//! A second push after the first: what a push sets up, weighed with it.
//!
//! Weighed alone, a push is worth the nearest its arc comes to the goal, so the planner took a
//! push that moved the object nearer while turning it away (the true θ in MuJoCo, pair 127: 135
//! mm nearer, 20° further off, then 40 s turning it back), and near the goal a push that gained a
//! millimetre from the face the pusher was at over one that left the object where another face
//! could finish it. Here each of the search's best pushes is weighed again as the first of two:
//! where it leaves the object (at its best length, and at half of it), then the best second push
//! from there, from any site of the grid, with the way round to it.
//!
//! It costs no model prediction beyond a few: a push's prediction is in the object's frame, so
//! the grid's predictions made for the first push serve the second from any pose, and the way
//! from one grid site to another's start is in the object's frame too, worked out once when the
//! planner is made. The first push's site is taken as the grid site nearest it for that way
//! (at most half the grid's spacing off); its own site's other directions are predicted, as
//! going on from where the pusher touches needs no way at all.

use nalgebra::Point2;

use crate::control::arc::BodyTwist;
use crate::control::sites::{APPROACH_M, Sites};
use crate::geometry::Pose2;

/// The ways from the grid's sites (the pusher touching there, as a push leaves it) to the start
/// of each of the grid's pushes, metres, in the object's frame.
#[derive(Clone, Debug, Default)]
pub struct GridWays {
    pushes: usize,
    ways: Vec<f64>,
}

impl GridWays {
    /// The ways for a grid of `sites` evenly round `sites_of`'s perimeter and `angles` directions
    /// at each, `angle_at(k)` the k-th direction.
    pub fn new(
        sites_of: &Sites,
        sites: usize,
        angles: usize,
        angle_at: impl Fn(usize) -> f64,
    ) -> Self {
        let mut path: Vec<Point2<f64>> = Vec::with_capacity(64);
        let pushes = sites * angles;
        let mut ways = vec![f64::INFINITY; sites * pushes];
        let grid_site = |i: usize| sites_of.site_at(sites_of.evenly(i, sites));
        for i in 0..sites {
            let Some(from) = grid_site(i) else { continue };
            let from = sites_of.touching(&from);
            for j in 0..sites {
                let Some(to) = grid_site(j) else { continue };
                for k in 0..angles {
                    let direction = Sites::push_direction(&to, angle_at(k));
                    let start = sites_of.approach(&to, direction);
                    ways[i * pushes + j * angles + k] =
                        sites_of.way(from, start, &mut path) + APPROACH_M;
                }
            }
        }
        Self { pushes, ways }
    }

    /// The way from grid site `from` (touching) to the start of grid push `push`.
    pub fn way(&self, from: usize, push: usize) -> f64 {
        self.ways
            .get(from * self.pushes + push)
            .copied()
            .unwrap_or(f64::INFINITY)
    }
}

/// The push after the first and its length, metres, where a push was weighed as the first of
/// two; `None`: stopping after the first is best.
pub type Next = Option<(Then, f64)>;

/// Which push goes on from the first: one of its own site's directions, or one of the grid's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Then {
    /// The first push's site, the k-th direction of the fan: no way to it.
    Here(usize),
    /// The grid's push of this index (site × directions + direction).
    Grid(usize),
}

/// The best way on from where the first push leaves the object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Onward {
    /// Its cost: the distance it ends at and what its pushing and way are weighed at.
    pub cost: f64,
    /// The planner's distance to the goal where it ends, metres.
    pub distance_m: f64,
    /// The second push.
    pub then: Next,
}

/// What a second push is weighed by: its arcs and the weights of the planner's cost.
pub struct Follow<'a> {
    /// The grid's pushes' twists (`None` where a grid site does not exist), grid order.
    pub grid: &'a [Option<BodyTwist>],
    /// The first push's own site's directions: going on from there needs no way.
    pub here: &'a [BodyTwist],
    pub ways: &'a GridWays,
    /// The grid site nearest the first push's.
    pub from: usize,
    pub reach_m: f64,
    pub lengths: usize,
    pub way_weight: f64,
    pub push_weight: f64,
}

impl Follow<'_> {
    /// The least cost of stopping at `pose` or going on with one more push from it, by
    /// `distance` (the planner's distance to the goal).
    pub fn best_from(&self, pose: &Pose2, distance: impl Fn(&Pose2) -> f64) -> Onward {
        let stay = distance(pose);
        let mut best = Onward {
            cost: stay,
            distance_m: stay,
            then: None,
        };
        let mut weigh = |which: Then, twist: &BodyTwist, way_cost: f64| {
            // The way alone costs more than the best found: no length of this push can win.
            if way_cost >= best.cost {
                return;
            }
            for k in 1..=self.lengths {
                let length = self.reach_m * (k as f64 / self.lengths as f64).powi(2);
                let d = distance(&twist.pose_after(pose, length));
                let cost = d + self.push_weight * length + way_cost;
                if cost < best.cost {
                    best = Onward {
                        cost,
                        distance_m: d,
                        then: Some((which, length)),
                    };
                }
            }
        };
        for (k, twist) in self.here.iter().enumerate() {
            weigh(Then::Here(k), twist, 0.0);
        }
        for (push, twist) in self.grid.iter().enumerate() {
            if let Some(twist) = twist {
                weigh(
                    Then::Grid(push),
                    twist,
                    self.way_weight * self.ways.way(self.from, push),
                );
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use nalgebra::Point2;

    use super::*;
    use crate::control::goal::Goal;
    use crate::control::planner::{Planner, PlannerConfig};
    use crate::control::predict::Predict;
    use crate::geometry::Outline;
    use crate::model::{ObjectMotion, SampleInput};

    /// A model where the object goes with the pusher, unturned: every arc is a straight line
    /// along the push, so what one push and two can do is plain geometry.
    struct Carried;

    impl Predict for Carried {
        fn motion(&self, input: &SampleInput) -> ObjectMotion {
            ObjectMotion {
                translation: input.robot_motion_in_object,
                rotation: 0.0,
            }
        }
    }

    fn plan_to(goal: Pose2, lookahead: bool) -> crate::control::Plan {
        let outline = Outline::rectangle(0.3, 0.4).unwrap();
        let config = PlannerConfig {
            lookahead,
            ..PlannerConfig::default()
        };
        let mut planner = Planner::new(&outline, 0.03, Goal::at(goal), 0.004, 0.04, config);
        let start = Pose2::new(0.0, 0.0, 0.0);
        planner
            .step_predicting(&start, Point2::new(-0.4, 0.0), &Carried)
            .clone()
    }

    /// A goal off to the side and ahead: no push within ±35° of straight in goes its way, so one
    /// push at a time stops short of it by its distance times sin 10°; two (one from behind, one
    /// from the side) reach it.
    #[test]
    fn two_pushes_reach_a_goal_no_single_push_points_at() {
        let goal = Pose2::new(0.1, 0.1, 0.0);
        let single = plan_to(goal, false);
        let single_push = single.push.unwrap();
        let off = 0.1 * std::f64::consts::SQRT_2 * 10f64.to_radians().sin();
        assert!(
            single_push.expected_distance_m > 0.95 * off,
            "{single_push:?}"
        );
        assert!(single_push.then.is_none() && single.then.is_empty());

        let pair = plan_to(goal, true);
        let push = pair.push.unwrap();
        let then = push.then.expect("a second push planned");
        assert!(push.expected_distance_m < 0.5 * off, "{push:?}");
        // The second push is from another face: the first leaves the object with the goal
        // straight ahead of it, not within the first face's fan.
        assert!(
            (then.site.normal - push.site.normal).norm() > 1.0,
            "{push:?}"
        );
        // What is drawn is what was weighed: the first arc ends where the second begins, and the
        // second ends at the distance the plan expects.
        let (joint, from) = (pair.predicted.last().unwrap(), pair.then.first().unwrap());
        assert!((joint.position - from.position).norm() < 1e-12 && joint.yaw == from.yaw);
        let end = pair.then.last().unwrap();
        assert!((Goal::at(goal).distance(end) - push.expected_distance_m).abs() < 1e-9);
    }

    #[test]
    fn ways_from_a_grid_site_are_the_sites_ways_and_nearest_sites_wrap() {
        let outline = Outline::rectangle(0.3, 0.4).unwrap();
        let sites = Sites::new(&outline, 0.03);
        let config = PlannerConfig::default();
        let angle_at = |k: usize| -0.5 + k as f64 / 6.0;
        let ways = GridWays::new(&sites, config.sites, 7, angle_at);
        let grid_site = |i: usize| sites.site_at(sites.evenly(i, config.sites)).unwrap();
        let mut path = Vec::new();
        for (i, j, k) in [(0, 0, 3), (0, 16, 0), (5, 30, 6), (31, 2, 1)] {
            let to = grid_site(j);
            let start = sites.approach(&to, Sites::push_direction(&to, angle_at(k)));
            let expected = sites.way(sites.touching(&grid_site(i)), start, &mut path) + APPROACH_M;
            assert!(
                (ways.way(i, j * 7 + k) - expected).abs() < 1e-12,
                "{i} {j} {k}"
            );
        }
        // Half round the box is farther than its own face.
        assert!(ways.way(0, 16 * 7 + 3) > ways.way(0, 3) + 0.3);
        let perimeter = sites.perimeter();
        assert_eq!(sites.evenly_nearest(0.0, 32), 0);
        assert_eq!(sites.evenly_nearest(perimeter - 1e-9, 32), 31);
        assert_eq!(sites.evenly_nearest(-0.01, 32), 31);
        assert_eq!(sites.evenly_nearest(perimeter * 16.5 / 32.0, 32), 16);
        assert_eq!(sites.evenly_nearest(sites.evenly(16, 32), 32), 16);
        assert_eq!(ways.way(32, 0), f64::INFINITY);
    }
}
