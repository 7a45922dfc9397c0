//! Transform trees of `tf2_msgs/msg/TFMessage` topics. Robots publish a tree, not one pose per
//! body: mocap gives `world → object` on `/tf`, while an arm's tip is `world → base_link` (static,
//! on `/tf_static`) `→ link1 … → tool0` (moving, on `/tf`) `→ tip` (a static offset). The pose that
//! `/tf:tip` names is the pose of `tip` in the root of its chain of parents (the frame that is no
//! one's child), composed from the transforms of the chosen topic and of `/tf_static`.
//!
//! Links are composed in 3-D (a wrist may be tilted while the tip is planar); only the result is
//! projected to x, y and the yaw. Each moving link is published at its own stamps, so the chain is
//! evaluated at the stamps of the chosen frame's own transforms (or, when that link is static, at
//! those of the chain's fastest moving link), and every other moving link is interpolated there:
//! translation linearly, rotation by slerp. A time outside a link's published span is not
//! extrapolated: that pose is dropped and counted.

use std::collections::HashMap;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use super::cdr::{self, Transform, yaw_of};
use super::problem::BagProblem;
use super::topic_info::TF_STATIC;

/// One transform of a child frame as published: `parent_from_child` at a time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Sample {
    /// The header stamp, or the log time when the stamp is zero; nanoseconds.
    pub ns: u64,
    pub stamped: bool,
    /// The file of the bag (its position in the file list) and the message's index on its topic in
    /// that file, for error messages.
    pub file: usize,
    pub index: u64,
    pub translation: [f64; 3],
    /// `[x, y, z, w]` as published.
    pub rotation: [f64; 4],
}

/// Every transform of one child frame on one topic.
#[derive(Debug)]
struct Link {
    child: String,
    parent: String,
    /// Another parent seen later (with its sample): a frame with two parents is no tree, but it only
    /// matters when a chain asked for goes through it.
    other_parent: Option<(String, Sample)>,
    samples: Vec<Sample>,
}

/// The transforms of one TFMessage topic, by child frame.
#[derive(Debug, Default)]
pub(super) struct TopicTransforms {
    topic: String,
    by_child: HashMap<Vec<u8>, usize>,
    /// In the order the child frames first appear.
    links: Vec<Link>,
    /// Messages seen on the topic in the current file: the index of the next one.
    index: u64,
}

impl TopicTransforms {
    fn link(&self, child: &str) -> Option<&Link> {
        self.by_child.get(child.as_bytes()).map(|&i| &self.links[i])
    }

    fn add(&mut self, transform: &Transform, sample: Sample) {
        let at = match self.by_child.get(transform.child) {
            Some(&at) => at,
            None => {
                self.by_child
                    .insert(transform.child.to_vec(), self.links.len());
                self.links.push(Link {
                    child: String::from_utf8_lossy(transform.child).into_owned(),
                    parent: String::from_utf8_lossy(transform.parent).into_owned(),
                    other_parent: None,
                    samples: Vec::new(),
                });
                self.links.len() - 1
            }
        };
        let link = &mut self.links[at];
        if link.parent.as_bytes() != transform.parent && link.other_parent.is_none() {
            let other = String::from_utf8_lossy(transform.parent).into_owned();
            link.other_parent = Some((other, sample));
        }
        link.samples.push(sample);
    }
}

/// The transforms of every TFMessage topic read: the pusher's and object's and `/tf_static`.
#[derive(Debug, Default)]
pub(super) struct Transforms {
    topics: Vec<TopicTransforms>,
}

impl Transforms {
    /// The slot of a topic's transforms, made empty the first time.
    pub fn slot(&mut self, topic: &str) -> usize {
        if let Some(at) = self.topics.iter().position(|t| t.topic == topic) {
            return at;
        }
        self.topics.push(TopicTransforms {
            topic: topic.to_owned(),
            ..TopicTransforms::default()
        });
        self.topics.len() - 1
    }

    /// Starts counting message indices again, as a new file of the bag begins.
    pub fn new_file(&mut self) {
        for topic in &mut self.topics {
            topic.index = 0;
        }
    }

    /// Keeps every transform of one message. Returns, for the pusher and the object (`frames`: the
    /// child frame each reads from this topic, if any), the time of its frame's first transform in
    /// the message, for the bag's time origin.
    pub fn record(
        &mut self,
        slot: usize,
        file: usize,
        log_time: u64,
        payload: &[u8],
        frames: [Option<&str>; 2],
    ) -> Result<[Option<u64>; 2], BagProblem> {
        let topic = &mut self.topics[slot];
        let index = topic.index;
        topic.index += 1;
        let mut firsts = [None; 2];
        let result = cdr::decode_tf(payload, |transform| {
            let sample = Sample {
                ns: if transform.stamp_ns == 0 {
                    log_time
                } else {
                    transform.stamp_ns
                },
                stamped: transform.stamp_ns != 0,
                file,
                index,
                translation: transform.translation,
                rotation: transform.rotation,
            };
            for (first, frame) in firsts.iter_mut().zip(frames) {
                if first.is_none() && frame.is_some_and(|f| f.as_bytes() == transform.child) {
                    *first = Some(sample.ns);
                }
            }
            topic.add(&transform, sample);
        });
        result.map_err(|why| BagProblem::Decode {
            topic: topic.topic.clone(),
            index,
            type_name: cdr::PoseType::TfMessage.name(),
            why,
        })?;
        Ok(firsts)
    }

    fn topic(&self, name: &str) -> Option<&TopicTransforms> {
        self.topics.iter().find(|t| t.topic == name)
    }

    /// The child frames of `topic`, then of `/tf_static`, in the order they first appear (at most
    /// 20), for saying which frames exist.
    pub fn frames_seen(&self, topic: &str) -> Vec<String> {
        let mut seen: Vec<String> = Vec::new();
        for name in [topic, TF_STATIC] {
            for link in self.topic(name).into_iter().flat_map(|t| &t.links) {
                if seen.len() < 20 && !seen.contains(&link.child) {
                    seen.push(link.child.clone());
                }
            }
        }
        seen
    }

    /// The chain from `frame` up to its root: each frame's transform on `topic` or, failing that,
    /// on `/tf_static`. `None` when `frame` is published on neither.
    pub fn chain<'a>(
        &'a self,
        topic: &'a str,
        frame: &str,
    ) -> Result<Option<Chain<'a>>, BagProblem> {
        let moving = self.topic(topic).filter(|_| topic != TF_STATIC);
        let fixed = self.topic(TF_STATIC);
        let find = |child: &str| {
            let on = |t: Option<&'a TopicTransforms>, moves| t?.link(child).map(|l| (l, moves));
            on(moving, true).or_else(|| on(fixed, false))
        };
        let mut frames = vec![frame.to_owned()];
        let mut links = Vec::new();
        while let Some((link, moves)) = find(&frames[frames.len() - 1]) {
            if let Some((second, sample)) = &link.other_parent {
                return Err(BagProblem::TwoParents {
                    topic: if moves { topic } else { TF_STATIC }.to_owned(),
                    frame: link.child.clone(),
                    parents: vec![link.parent.clone(), second.clone()],
                    index: sample.index,
                });
            }
            let looped = frames.contains(&link.parent);
            frames.push(link.parent.clone());
            if looped {
                return Err(BagProblem::FrameLoop {
                    topic: topic.to_owned(),
                    chain: frames,
                });
            }
            links.push(ChainLink {
                link,
                topic: if moves { topic } else { TF_STATIC },
                moves,
            });
        }
        Ok((!links.is_empty()).then_some(Chain {
            topic,
            frames,
            links,
        }))
    }
}

/// One link of a chain: a child frame's transforms and whether they move (are not static).
#[derive(Debug)]
struct ChainLink<'a> {
    link: &'a Link,
    topic: &'a str,
    moves: bool,
}

/// The links from a frame up to its root.
#[derive(Debug)]
pub(super) struct Chain<'a> {
    /// The topic asked for.
    topic: &'a str,
    /// The frame asked for, its parent, …, the root.
    pub frames: Vec<String>,
    /// `links[k]` is `frames[k + 1]_from_frames[k]`.
    links: Vec<ChainLink<'a>>,
}

/// A pose of the chain's frame in its root, at one time of the link that sets the times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RootPose {
    /// The sample of the link whose times the chain is evaluated at.
    pub at: Sample,
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

/// Poses dropped because a moving link of the chain was not published around their time.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Dropped {
    pub count: usize,
    /// The first link that lacked them, `parent → child`, and its published span, nanoseconds.
    pub link: String,
    pub span_ns: (u64, u64),
}

/// The chain's poses in its root, with the topic of the link that sets the times.
#[derive(Debug)]
pub(super) struct ChainPoses<'a> {
    pub poses: Vec<RootPose>,
    /// The topic the times come from (the one asked for, or `/tf_static` when all is static).
    pub topic: &'a str,
    /// How many poses the chain would have without drops.
    pub candidates: usize,
    pub dropped: Option<Dropped>,
}

/// A link prepared for evaluation.
enum Prepared {
    /// The latest transform published (tf2 keeps the latest static transform).
    Fixed(Isometry3<f64>),
    /// Transforms sorted by time.
    Moving(Vec<(u64, Isometry3<f64>)>),
    /// The link that sets the times: each of its own transforms is used as published.
    Times,
}

impl<'a> Chain<'a> {
    pub fn root(&self) -> &str {
        &self.frames[self.frames.len() - 1]
    }

    /// The link whose stamps the chain is evaluated at: the frame's own transform when it is on the
    /// topic asked for, else the fastest moving link; `None` when every link is static.
    fn times_link(&self) -> Option<usize> {
        if self.links[0].moves || self.topic == TF_STATIC {
            return Some(0);
        }
        let rate = |l: &ChainLink| {
            let (first, last) = span(&l.link.samples);
            let seconds = last.saturating_sub(first) as f64 * 1e-9;
            if l.link.samples.len() < 2 || seconds <= 0.0 {
                0.0
            } else {
                (l.link.samples.len() - 1) as f64 / seconds
            }
        };
        let mut best: Option<(usize, f64)> = None;
        for (k, link) in self.links.iter().enumerate().filter(|(_, l)| l.moves) {
            let r = rate(link);
            if best.is_none_or(|(_, b)| r > b) {
                best = Some((k, r));
            }
        }
        best.map(|(k, _)| k)
    }

    /// The frame's poses in the root at the times of the chain's timing link, in file order. Errors
    /// name the file (by its position in the bag's list) when a transform is unusable.
    pub fn poses(&self, spec: &str) -> Result<ChainPoses<'a>, (Option<usize>, BagProblem)> {
        let Some(times) = self.times_link() else {
            return Err((
                None,
                BagProblem::StaticChain {
                    spec: spec.to_owned(),
                    topic: self.topic.to_owned(),
                    chain: self.frames.clone(),
                },
            ));
        };
        let driver = &self.links[times];
        let mut out = ChainPoses {
            poses: Vec::with_capacity(driver.link.samples.len()),
            topic: driver.topic,
            candidates: driver.link.samples.len(),
            dropped: None,
        };
        // A frame published directly under its root: its transforms are its poses, as published.
        if self.links.len() == 1 {
            out.poses.extend(driver.link.samples.iter().map(|s| {
                let yaw = yaw_of(s.rotation);
                RootPose {
                    at: *s,
                    x: s.translation[0],
                    y: s.translation[1],
                    yaw,
                }
            }));
            return Ok(out);
        }
        let prepared = self
            .links
            .iter()
            .enumerate()
            .map(|(k, l)| prepare(l, k == times))
            .collect::<Result<Vec<_>, _>>()?;
        let mut lacking: Vec<usize> = vec![0; self.links.len()];
        for sample in &driver.link.samples {
            let own = isometry(driver, sample)?;
            let mut root_from_frame = Isometry3::identity();
            let mut missing = None;
            for (k, link) in prepared.iter().enumerate() {
                let parent_from_child = match link {
                    Prepared::Fixed(iso) => *iso,
                    Prepared::Times => own,
                    Prepared::Moving(samples) => match interpolate(samples, sample.ns) {
                        Some(iso) => iso,
                        None => {
                            missing = Some(k);
                            break;
                        }
                    },
                };
                root_from_frame = parent_from_child * root_from_frame;
            }
            if let Some(k) = missing {
                lacking[k] += 1;
                continue;
            }
            let q = root_from_frame.rotation.quaternion().coords;
            let t = root_from_frame.translation.vector;
            out.poses.push(RootPose {
                at: *sample,
                x: t.x,
                y: t.y,
                yaw: yaw_of([q.x, q.y, q.z, q.w]),
            });
        }
        let count = lacking.iter().sum();
        if let Some(k) = lacking.iter().position(|&n| n > 0) {
            let link = self.links[k].link;
            out.dropped = Some(Dropped {
                count,
                link: format!("{} → {}", link.parent, link.child),
                span_ns: span(&link.samples),
            });
        }
        Ok(out)
    }
}

/// The earliest and latest time of some samples, nanoseconds.
fn span(samples: &[Sample]) -> (u64, u64) {
    let first = samples.iter().map(|s| s.ns).min().unwrap_or(0);
    let last = samples.iter().map(|s| s.ns).max().unwrap_or(0);
    (first, last)
}

fn prepare(link: &ChainLink, times: bool) -> Result<Prepared, (Option<usize>, BagProblem)> {
    if times {
        return Ok(Prepared::Times);
    }
    if !link.moves {
        let latest = link.link.samples.last().map(|s| isometry(link, s));
        return Ok(Prepared::Fixed(
            latest.transpose()?.unwrap_or_else(Isometry3::identity),
        ));
    }
    let mut samples = link
        .link
        .samples
        .iter()
        .map(|s| Ok((s.ns, isometry(link, s)?)))
        .collect::<Result<Vec<_>, _>>()?;
    samples.sort_by_key(|(ns, _)| *ns);
    Ok(Prepared::Moving(samples))
}

/// A sample as `parent_from_child`, its rotation normalised; an error when it has no rotation.
fn isometry(link: &ChainLink, s: &Sample) -> Result<Isometry3<f64>, (Option<usize>, BagProblem)> {
    let Some(iso) = isometry_of(s.translation, s.rotation) else {
        return Err((
            Some(s.file),
            BagProblem::BadValue {
                topic: link.topic.to_owned(),
                index: s.index,
                why: format!(
                    "transform {} → {} has translation {:?} and rotation {:?}, expected finite \
                     numbers and a quaternion of nonzero length",
                    link.link.parent, link.link.child, s.translation, s.rotation
                ),
            },
        ));
    };
    Ok(iso)
}

/// A transform as published (`[x, y, z, w]` rotation) as an isometry, its rotation normalised;
/// `None` when a number is not finite or the quaternion has no length. A live session's chains
/// read transforms by this rule too, so that they compose as an import does.
pub(crate) fn isometry_of(translation: [f64; 3], rotation: [f64; 4]) -> Option<Isometry3<f64>> {
    let [x, y, z, w] = rotation;
    let q = Quaternion::new(w, x, y, z);
    let norm = q.norm();
    let finite = translation.iter().all(|v| v.is_finite());
    (finite && norm.is_finite() && norm > 1e-9).then(|| {
        Isometry3::from_parts(
            Translation3::from(translation),
            UnitQuaternion::from_quaternion(q),
        )
    })
}

/// `parent_from_child` at `ns` from the samples around it (sorted by time): the translation
/// linearly, the rotation by slerp. `None` outside the samples' span: not extrapolated.
pub(crate) fn interpolate(samples: &[(u64, Isometry3<f64>)], ns: u64) -> Option<Isometry3<f64>> {
    let i = samples.partition_point(|(t, _)| *t <= ns);
    let (before_ns, before) = samples.get(i.checked_sub(1)?)?;
    if *before_ns == ns {
        return Some(*before);
    }
    let (after_ns, after) = samples.get(i)?;
    let w = (ns - before_ns) as f64 / (after_ns - before_ns) as f64;
    let translation = before.translation.vector.lerp(&after.translation.vector, w);
    // Rotations exactly half a turn apart have no one shortest path; keep the earlier then.
    let rotation = before
        .rotation
        .try_slerp(&after.rotation, w, 1e-12)
        .unwrap_or(before.rotation);
    Some(Isometry3::from_parts(translation.into(), rotation))
}

#[cfg(test)]
mod tests;
