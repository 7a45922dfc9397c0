//! The planner's side of the lookahead ([`super::lookahead`]): a push weighed as the first of
//! two, and the site of the second. Apart from the lookahead's pieces so that they need nothing
//! of the planner's.

use super::lookahead::{Follow, Next, Then};
use super::{Candidate, Planner, Weighing};
use crate::control::predict::Predict;
use crate::control::sites::{Site, Sites};

impl Planner {
    /// `first` weighed as the first of two pushes ([`super::lookahead`]): itself where
    /// going on from it, at its length or half of it, is worth no more.
    pub(super) fn two_pushes<P: Predict + ?Sized>(
        &mut self,
        w: &Weighing<'_, P>,
        first: &Candidate,
    ) -> (Candidate, Next) {
        let c = self.config;
        let Some(site) = self.sites.site_at(first.along) else {
            return (*first, None);
        };
        let twist = self.twist_of(w, &site, Sites::push_direction(&site, first.angle));
        // The margin the kept push was given, given again.
        let margin = match self.kept {
            Some(kept) if kept.along == first.along && kept.angle == first.angle => c.keep_margin_m,
            _ => 0.0,
        };
        self.here_twists.clear();
        for k in 0..c.angles {
            let direction = Sites::push_direction(&site, c.angle_at(k));
            let twist = self.twist_of(w, &site, direction);
            self.here_twists.push(twist);
        }
        self.plan.predictions += c.angles + 1;
        let follow = Follow {
            grid: &self.grid_twists,
            here: &self.here_twists,
            ways: &self.ways,
            from: self.sites.evenly_nearest(first.along, c.sites),
            reach_m: c.reach_m,
            lengths: c.follow_lengths,
            way_weight: c.way_weight,
            push_weight: c.push_weight,
        };
        let goal = self.goal;
        let mut best = (*first, None);
        for length in [first.length_m, 0.5 * first.length_m] {
            let pose = twist.pose_after(&w.object, length);
            let onward = follow.best_from(&pose, |p| goal.distance(p));
            if onward.distance_m >= w.distance_now - c.least_gain_m {
                continue;
            }
            let cost = c.way_weight * first.way_m + c.push_weight * length + onward.cost - margin;
            if cost < best.0.cost {
                best = (
                    Candidate {
                        cost,
                        length_m: length,
                        distance_m: onward.distance_m,
                        ..*first
                    },
                    onward.then,
                );
            }
        }
        best
    }

    /// The site and direction of the push after `first`'s site.
    pub(super) fn then_push(&self, first: &Site, then: Then) -> Option<(Site, f64)> {
        let c = &self.config;
        match then {
            Then::Here(k) => Some((*first, c.angle_at(k))),
            Then::Grid(push) => {
                let (i, k) = (push / c.angles.max(1), push % c.angles.max(1));
                Some((
                    self.sites.site_at(self.sites.evenly(i, c.sites))?,
                    c.angle_at(k),
                ))
            }
        }
    }
}
