//! A TF child frame followed live through its chain of parents, as a bag's `/tf:FRAME` is read
//! (`recording::bag::tf_tree`): the frame's pose in the root of its chain (the frame that is no
//! one's child), each link taken from the followed topic or, failing that, from `/tf_static`, and
//! composed in 3-D before the result is projected to x, y and the yaw.
//!
//! A bag has all its transforms at hand; a live session has those that have arrived. So:
//! - **The chain is fixed once**, when the frame's first transforms can be composed: after the
//!   first `/tf_static` message if the server advertises that topic, or half a second (of the
//!   followed topic's stamps) after its first message, whichever comes first. A frame that later
//!   gets a parent above the root is said, and the poses stay in the root they began in.
//! - **Each pose waits** until every other moving link of the chain has a transform at or after
//!   its time, then is composed with those links interpolated there (translation linearly,
//!   rotation by slerp: the import's own functions), so that it is the pose the recording's
//!   import gives. A pose whose links began after it, or that waited a second for a link that
//!   stopped, is dropped and counted, as the import drops what it cannot interpolate.
//! - **Memory stays bounded**: only the transforms of the chain's links still needed for the
//!   poses waiting are kept (before the chain is fixed: at most [`MAX_HELD`] of each frame).
//!
//! The times come from the frame's own transforms, or — when its own link is static — from the
//! nearest moving link above it (a bag takes the fastest moving link: the same one when the links
//! are published together, as `robot_state_publisher` does).

use std::collections::{HashMap, VecDeque};

use nalgebra::Isometry3;

use crate::recording::bag::{PlanarPose, decode_tf, interpolate, isometry_of, yaw_of};

/// How long after the followed topic's first transform the chain is fixed without `/tf_static`,
/// nanoseconds of its stamps.
const SETTLE_NS: u64 = 500_000_000;
/// How long a pose waits for a link of its chain to catch up, nanoseconds of the times link's
/// stamps: then it is dropped.
const WAIT_NS: u64 = 1_000_000_000;
/// Transforms kept of each frame before the chain is fixed.
const MAX_HELD: usize = 5_000;

/// One transform as published: its time (the stamp, or the log time when the stamp is zero), the
/// translation and the rotation `[x, y, z, w]`.
#[derive(Clone, Copy, Debug)]
struct Published {
    ns: u64,
    translation: [f64; 3],
    rotation: [f64; 4],
}

/// A child frame's link: its parent and its transforms (sorted by time, as the import sorts them),
/// as isometries and as published.
#[derive(Debug, Default)]
struct Link {
    parent: String,
    samples: Vec<(u64, Isometry3<f64>)>,
    published: Vec<Published>,
}

impl Link {
    /// Inserts after the transforms of the same time, as the import's stable sort keeps them.
    fn insert(&mut self, sample: Published, iso: Isometry3<f64>) {
        let at = self.samples.partition_point(|(ns, _)| *ns <= sample.ns);
        self.samples.insert(at, (sample.ns, iso));
        self.published.insert(at, sample);
        if self.samples.len() > MAX_HELD {
            self.samples.remove(0);
            self.published.remove(0);
        }
    }

    fn newest_ns(&self) -> Option<u64> {
        self.samples.last().map(|(ns, _)| *ns)
    }

    /// Forgets the transforms before the last one at or before `ns`.
    fn forget_before(&mut self, ns: u64) {
        let first_kept = (self.samples.partition_point(|(t, _)| *t <= ns)).saturating_sub(1);
        self.samples.drain(..first_kept);
        self.published.drain(..first_kept);
    }
}

/// Where a link of the fixed chain is read from.
#[derive(Clone, Debug, PartialEq)]
enum From {
    /// The followed topic's transforms of this child frame.
    Moving(String),
    /// The latest `/tf_static` transform of this child frame.
    Fixed(String),
}

/// The chain once fixed: its links from the frame up, and the one whose transforms give the times.
#[derive(Debug)]
struct Fixed {
    links: Vec<From>,
    /// The frame asked for, its parent, …, the root.
    frames: Vec<String>,
    times: usize,
}

/// What one message gave: poses, and sentences for the user.
#[derive(Debug, Default, PartialEq)]
pub struct ChainRead {
    pub poses: Vec<PlanarPose>,
    pub said: Vec<String>,
}

/// A TF frame followed through its chain (see the module documentation).
#[derive(Debug)]
pub struct LiveChain {
    frame: String,
    moving: HashMap<String, Link>,
    fixed_links: HashMap<String, (String, Isometry3<f64>)>,
    chain: Option<Fixed>,
    /// Transforms of the times link waiting for the chain's other moving links.
    pending: VecDeque<(Published, Isometry3<f64>)>,
    expects_static: bool,
    static_seen: bool,
    /// The followed topic's first transform time: when the chain may be fixed without `/tf_static`.
    first_ns: Option<u64>,
    dropped: usize,
    /// The time of the last pose composed or dropped.
    done_ns: Option<u64>,
    said_root_parent: bool,
}

impl LiveChain {
    /// Follows `frame`; `expects_static`: the server advertises `/tf_static` (wait for it before
    /// fixing the chain).
    pub fn new(frame: &str, expects_static: bool) -> Self {
        Self {
            frame: frame.to_owned(),
            moving: HashMap::new(),
            fixed_links: HashMap::new(),
            chain: None,
            pending: VecDeque::new(),
            expects_static,
            static_seen: false,
            first_ns: None,
            dropped: 0,
            done_ns: None,
            said_root_parent: false,
        }
    }

    /// The server advertised `/tf_static` (after the session began).
    pub fn expect_static(&mut self) {
        self.expects_static = true;
    }

    /// Poses dropped: their chain could not be composed at their time.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// Transforms held: those waiting to be posed and those kept to interpolate them.
    pub fn held(&self) -> usize {
        self.pending.len() + self.moving.values().map(|l| l.samples.len()).sum::<usize>()
    }

    /// The chain once fixed: the frame, its parent, …, the root.
    pub fn frames(&self) -> Option<&[String]> {
        self.chain.as_ref().map(|c| c.frames.as_slice())
    }

    /// Reads one TFMessage received at `log_time_ns`, from the followed topic or (`is_static`) from
    /// `/tf_static`. A message with a transform that does not decode or is not a rigid motion is
    /// refused whole, in words.
    pub fn add(
        &mut self,
        payload: &[u8],
        log_time_ns: u64,
        is_static: bool,
    ) -> Result<ChainRead, String> {
        let mut transforms = Vec::new();
        let mut bad = None;
        decode_tf(payload, |t| {
            let published = Published {
                ns: if t.stamp_ns == 0 {
                    log_time_ns
                } else {
                    t.stamp_ns
                },
                translation: t.translation,
                rotation: t.rotation,
            };
            let child = String::from_utf8_lossy(t.child).into_owned();
            let parent = String::from_utf8_lossy(t.parent).into_owned();
            match isometry_of(t.translation, t.rotation) {
                Some(iso) => transforms.push((parent, child, published, iso)),
                None => {
                    bad.get_or_insert(format!(
                        "transform {parent} → {child} has translation {:?} and rotation {:?}, \
                         expected finite numbers and a quaternion of nonzero length",
                        t.translation, t.rotation
                    ));
                }
            }
        })?;
        if let Some(bad) = bad {
            return Err(bad);
        }
        let mut read = ChainRead::default();
        for (parent, child, published, iso) in transforms {
            self.keep(parent, child, published, iso, is_static, &mut read);
        }
        if is_static {
            self.static_seen = true;
        }
        if self.chain.is_none() {
            self.try_fix(&mut read);
        }
        self.compose(&mut read);
        self.trim();
        Ok(read)
    }

    /// Keeps one transform where the chain will look for it.
    fn keep(
        &mut self,
        parent: String,
        child: String,
        published: Published,
        iso: Isometry3<f64>,
        is_static: bool,
        read: &mut ChainRead,
    ) {
        if let Some(chain) = &self.chain
            && chain.frames.last() == Some(&child)
            && !self.said_root_parent
        {
            self.said_root_parent = true;
            read.said.push(format!(
                "the frame {child} got the parent {parent} after the poses of {} began in it: \
                 they stay in {child}",
                self.frame
            ));
        }
        if is_static {
            // tf2 keeps the latest static transform of a frame.
            self.fixed_links.insert(child, (parent, iso));
            return;
        }
        self.first_ns.get_or_insert(published.ns);
        let times_child = (self.chain.as_ref()).map(|c| &c.links[c.times]);
        if times_child == Some(&From::Moving(child.clone())) {
            self.pending.push_back((published, iso));
            return;
        }
        let in_chain = self
            .chain
            .as_ref()
            .is_none_or(|c| c.links.contains(&From::Moving(child.clone())));
        if in_chain {
            let link = self.moving.entry(child).or_insert_with(|| Link {
                parent: parent.clone(),
                ..Link::default()
            });
            // A second parent is no tree: the first one stays (the import refuses such a chain).
            if link.parent == parent {
                link.insert(published, iso);
            }
        }
    }

    /// Fixes the chain from the links seen, once `/tf_static` came or the settling time passed.
    fn try_fix(&mut self, read: &mut ChainRead) {
        let newest = self.moving.values().filter_map(Link::newest_ns).max();
        let settled = (self.first_ns.zip(newest)).is_some_and(|(a, b)| b >= a + SETTLE_NS);
        if !(self.static_seen || !self.expects_static || settled) {
            return;
        }
        let mut frames = vec![self.frame.clone()];
        let mut links = Vec::new();
        loop {
            let child = &frames[frames.len() - 1];
            let (from, parent) = match (self.moving.get(child), self.fixed_links.get(child)) {
                (Some(link), _) => (From::Moving(child.clone()), link.parent.clone()),
                (None, Some((parent, _))) => (From::Fixed(child.clone()), parent.clone()),
                (None, None) => break,
            };
            if frames.contains(&parent) {
                // A loop has no root; wait for the tree to be put right.
                return;
            }
            links.push(from);
            frames.push(parent);
        }
        let Some(times) = links.iter().position(|l| matches!(l, From::Moving(_))) else {
            // The frame is not seen yet, or every link is static: no times to pose it at.
            return;
        };
        read.said.push(format!(
            "following {} through {}",
            self.frame,
            frames[1..].join(" → ")
        ));
        let From::Moving(times_child) = &links[times] else {
            return;
        };
        if let Some(link) = self.moving.remove(times_child) {
            let isometries = link.samples.iter().map(|(_, iso)| *iso);
            self.pending
                .extend(link.published.into_iter().zip(isometries));
        }
        self.chain = Some(Fixed {
            links,
            frames,
            times,
        });
    }

    /// Composes the poses waiting whose links have caught up, in order.
    fn compose(&mut self, read: &mut ChainRead) {
        let Some(chain) = &self.chain else {
            return;
        };
        let newest_time = self.pending.back().map_or(0, |(p, _)| p.ns);
        while let Some(&(at, own)) = self.pending.front() {
            // A frame published directly under its root: its transforms are its poses, as
            // published (the import's rule for a one-link chain).
            if chain.links.len() == 1 {
                read.poses.push(PlanarPose {
                    stamp_ns: at.ns,
                    x: at.translation[0],
                    y: at.translation[1],
                    yaw: yaw_of(at.rotation),
                });
                self.pending.pop_front();
                self.done_ns = Some(at.ns);
                continue;
            }
            let mut root_from_frame = Isometry3::identity();
            let mut wait = false;
            let mut lacking = false;
            for (k, from) in chain.links.iter().enumerate() {
                let parent_from_child = if k == chain.times {
                    own
                } else {
                    match from {
                        From::Fixed(child) => self.fixed_links[child].1,
                        From::Moving(child) => {
                            let link = self.moving.get(child);
                            let samples = link.map_or(&[][..], |l| &l.samples);
                            match interpolate(samples, at.ns) {
                                Some(iso) => iso,
                                None => {
                                    let behind = link
                                        .and_then(Link::newest_ns)
                                        .is_none_or(|newest| newest < at.ns);
                                    if behind && newest_time < at.ns + WAIT_NS {
                                        wait = true;
                                    } else {
                                        lacking = true;
                                    }
                                    break;
                                }
                            }
                        }
                    }
                };
                root_from_frame = parent_from_child * root_from_frame;
            }
            if wait {
                break;
            }
            self.pending.pop_front();
            self.done_ns = Some(at.ns);
            if lacking {
                self.dropped += 1;
                continue;
            }
            let q = root_from_frame.rotation.quaternion().coords;
            let t = root_from_frame.translation.vector;
            read.poses.push(PlanarPose {
                stamp_ns: at.ns,
                x: t.x,
                y: t.y,
                yaw: yaw_of([q.x, q.y, q.z, q.w]),
            });
        }
    }

    /// Drops the transforms no pose waiting or to come needs: of each moving link, those before the
    /// last one at or before the oldest pose waiting (or, with none waiting, the last one composed).
    fn trim(&mut self) {
        if self.chain.is_none() {
            return;
        }
        let Some(needed) = self.pending.front().map(|(p, _)| p.ns).or(self.done_ns) else {
            return;
        };
        for link in self.moving.values_mut() {
            link.forget_before(needed);
        }
    }
}

#[cfg(test)]
mod tests;
