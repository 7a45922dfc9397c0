//! Reading the pusher's and the object's raw poses from a bag: one pass over its messages, decoding
//! the two streams' topics (and the transform trees of `/tf` frames).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::camera::{BagBytes, FoundCamera};
use super::cdr::{self, PoseType};
use super::error::BagError;
use super::files::{bag_files, read_file};
use super::image_msg::{self, ImageKind};
use super::mcap::{ChannelInfo, Visit, Visitor, Want, read_messages};
use super::message;
use super::problem::BagProblem;
use super::spec::TopicSpec;
use super::tf_tree::{Chain, Transforms};
use super::topic_info::{TF_STATIC, TopicInfo};
use super::topics::{TopicTable, cut_of};
use crate::recording::progress::{NoProgress, Progress};
use crate::recording::resample::MAX_POSITION_M;

/// How a file of the bag was cut short.
#[derive(Clone, Debug, PartialEq)]
pub struct FileCut {
    /// The sentence that says where and what was lost.
    pub said: String,
    /// Whether messages were lost (a warning) or only the records after them (a note).
    pub messages_lost: bool,
}

impl FileCut {
    /// Says the cut among `warnings` when it lost messages, else among `notes`.
    pub fn say(self, warnings: &mut Vec<String>, notes: &mut Vec<String>) {
        let among = if self.messages_lost { warnings } else { notes };
        among.push(self.said);
    }
}

/// The raw pose streams of the pusher and the object, rows `[t, x, y, yaw]` with `t` in seconds
/// since `base_unix_ns`, in file order (not yet cleaned).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BagStreams {
    pub pusher: Vec<[f64; 4]>,
    pub object: Vec<[f64; 4]>,
    /// Unix time, nanoseconds, that `t = 0` stands for: the first pose's time.
    pub base_unix_ns: u64,
    /// Every topic of the bag.
    pub topics: Vec<TopicInfo>,
    /// Recoverable defects found while reading (`/tf` poses dropped outside a moving link's span, an
    /// earlier file of a rosbag2 folder cut short), said of every push.
    pub warnings: Vec<String>,
    /// What reading did that loses nothing (header stamps missing, log times used), said of every
    /// push.
    pub notes: Vec<String>,
    /// The bag's last file cut short: said of the last push alone, the one the cut ends (a cut in
    /// an earlier file of a rosbag2 folder is one of `warnings`, or of `notes` when it lost no
    /// message).
    pub cut_short: Option<FileCut>,
    /// The frames of the camera topics asked for, in the order asked.
    pub cameras: Vec<FoundCamera>,
    /// Where the bag's bytes are, for reading the frames later.
    pub bag: BagBytes,
}

/// Per-stream reading state.
struct Stream<'a> {
    spec: &'a TopicSpec,
    rows: Vec<[f64; 4]>,
    /// Messages seen on the topic in the current file, for error messages.
    index: u64,
    unstamped: u64,
}

/// What the messages of one channel are read for, decided once per channel.
#[derive(Clone, Copy)]
enum Role {
    /// Single poses feeding the streams flagged.
    Poses([bool; 2], PoseType),
    /// Transforms, kept in the given slot of [`Transforms`] for resolving the tree after reading;
    /// the streams flagged read their child frames from this topic.
    Tf([bool; 2], usize),
    /// Frames of the camera asked for in this place.
    Camera(usize),
}

/// Reads the pusher's and the object's poses from a bag, and indexes the frames of the camera
/// topics named. A topic that is missing or of a type pushlab cannot read is refused with the bag's
/// topics; a `/tf` frame never published, with the frames that were; two `/tf` frames in trees of
/// different roots, with both chains.
pub fn read_streams(
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    cameras: &[String],
    progress: &dyn Progress,
) -> Result<BagStreams, BagError> {
    let files = bag_files(path)?;
    let bag = BagBytes::Files(files.clone().into());
    read_streams_in(path, &files, None, bag, pusher, object, cameras, progress)
}

/// [`read_streams`] of one `.mcap` file held in memory; `path` is only used in messages.
pub fn read_streams_bytes(
    bytes: &[u8],
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    cameras: &[String],
) -> Result<BagStreams, BagError> {
    // The bytes are kept for reading frames later only when there are frames to read.
    let kept = if cameras.is_empty() { &[][..] } else { bytes };
    let bag = BagBytes::Memory {
        path: path.to_path_buf(),
        bytes: Arc::from(kept),
    };
    let files = [path.to_path_buf()];
    read_streams_in(
        path,
        &files,
        Some(bytes),
        bag,
        pusher,
        object,
        cameras,
        &NoProgress,
    )
}

#[allow(clippy::too_many_arguments)] // one private place that both entry points fill
fn read_streams_in(
    path: &Path,
    files: &[PathBuf],
    bytes: Option<&[u8]>,
    bag: BagBytes,
    pusher: &TopicSpec,
    object: &TopicSpec,
    cameras: &[String],
    progress: &dyn Progress,
) -> Result<BagStreams, BagError> {
    let mut streams = [pusher, object].map(|spec| Stream {
        spec,
        rows: Vec::new(),
        index: 0,
        unstamped: 0,
    });
    let mut table = TopicTable::default();
    let mut transforms = Transforms::default();
    let wants_tree = pusher.child_frame.is_some() || object.child_frame.is_some();
    let mut base: Option<u64> = None;
    let mut found: Vec<Option<FoundCamera>> = vec![None; cameras.len()];
    let (mut warnings, mut notes) = (Vec::new(), Vec::new());
    let mut cut_short = None;
    for (file_number, file) in files.iter().enumerate() {
        for stream in &mut streams {
            stream.index = 0;
        }
        transforms.new_file();
        let mut visitor = PoseVisitor {
            streams: &mut streams,
            transforms: &mut transforms,
            base: &mut base,
            roles: HashMap::new(),
            wants_tree,
            file_number,
            camera_topics: cameras,
            cameras: &mut found,
            progress,
        };
        let read = read_file(file, bytes, |source| read_messages(source, &mut visitor))?;
        for (channel, stats) in read.channels.values() {
            table.add(channel, stats);
        }
        if let Some(cut) = read.cut_short {
            let cut = FileCut {
                said: cut_of(path, file, cut),
                messages_lost: cut.messages_lost,
            };
            if file_number + 1 == files.len() {
                cut_short = Some(cut);
            } else {
                cut.say(&mut warnings, &mut notes);
            }
        }
    }
    let bag_error = |problem| BagError::Problem {
        path: path.to_path_buf(),
        problem,
    };
    let mut chains = [None, None];
    for (stream, chain) in streams.iter().zip(&mut chains) {
        let spec = stream.spec;
        let Some(info) = table.get(&spec.topic) else {
            return Err(bag_error(BagProblem::MissingTopic {
                topic: spec.topic.clone(),
                available: table.listing(),
            }));
        };
        let Some(kind) = info.pose_type() else {
            return Err(bag_error(BagProblem::UnsupportedType {
                topic: spec.topic.clone(),
                type_name: info.type_name.clone(),
                encoding: info.encoding.clone(),
                available: table.listing(),
            }));
        };
        if kind == PoseType::TfMessage
            && let Some(frame) = &spec.child_frame
        {
            let found = transforms.chain(&spec.topic, frame).map_err(bag_error)?;
            let Some(found) = found else {
                return Err(bag_error(BagProblem::NoChildFrame {
                    topic: spec.topic.clone(),
                    frame: frame.clone(),
                    seen: transforms.frames_seen(&spec.topic),
                }));
            };
            *chain = Some(found);
        }
    }
    if let [Some(tip), Some(obj)] = &chains
        && tip.root() != obj.root()
    {
        return Err(bag_error(BagProblem::DifferentRoots {
            pusher: pusher.to_string(),
            pusher_chain: tip.frames.clone().into_boxed_slice(),
            object: object.to_string(),
            object_chain: obj.frames.clone().into_boxed_slice(),
        }));
    }
    for (stream, chain) in streams.iter_mut().zip(&chains) {
        if let Some(chain) = chain {
            read_chain(stream, chain, files, path, &mut base, &mut warnings)?;
        }
        if stream.unstamped > 0 {
            notes.push(format!(
                "{}: {} of {} pose(s) without a header stamp; their log time used",
                stream.spec,
                stream.unstamped,
                stream.rows.len()
            ));
        }
    }
    let mut found_cameras = Vec::with_capacity(cameras.len());
    for (topic, camera) in cameras.iter().zip(found) {
        let Some(camera) = camera else {
            let problem = match table.get(topic) {
                None => BagProblem::MissingTopic {
                    topic: topic.clone(),
                    available: table.listing(),
                },
                Some(info) => BagProblem::NotACamera {
                    topic: topic.clone(),
                    type_name: info.type_name.clone(),
                    encoding: info.encoding.clone(),
                },
            };
            return Err(bag_error(problem));
        };
        if camera.unstamped > 0 {
            notes.push(format!(
                "camera {topic}: {} of {} frame(s) without a header stamp; their log time used",
                camera.unstamped,
                camera.frames.len()
            ));
        }
        found_cameras.push(camera);
    }
    let [pusher_stream, object_stream] = streams;
    Ok(BagStreams {
        pusher: pusher_stream.rows,
        object: object_stream.rows,
        base_unix_ns: base.unwrap_or(0),
        topics: table.into_sorted(),
        warnings,
        notes,
        cut_short,
        cameras: found_cameras,
        bag,
    })
}

/// The error for a TFMessage topic named without a child frame, listing the frames of `payload`.
fn need_child_frame(topic: &str, payload: &[u8]) -> BagProblem {
    let mut seen = Vec::new();
    // The message decoded once already: this cannot fail.
    let _ = cdr::decode_tf(payload, |t| {
        seen.push(String::from_utf8_lossy(t.child).into_owned());
    });
    BagProblem::NeedChildFrame {
        topic: topic.to_owned(),
        seen,
    }
}

/// Fills a `/tf` stream's rows with its frame's poses in the root of its chain.
fn read_chain(
    stream: &mut Stream,
    chain: &Chain,
    files: &[PathBuf],
    path: &Path,
    base: &mut Option<u64>,
    warnings: &mut Vec<String>,
) -> Result<(), BagError> {
    let spec = stream.spec.to_string();
    let error = |file: Option<usize>, problem| BagError::Problem {
        path: file
            .and_then(|f| files.get(f))
            .map_or_else(|| path.to_path_buf(), Clone::clone),
        problem,
    };
    let found = chain.poses(&spec).map_err(|(file, p)| error(file, p))?;
    let Some(first) = found.poses.first() else {
        return Ok(());
    };
    let base = *base.get_or_insert(first.at.ns);
    stream.rows.reserve(found.poses.len());
    for pose in &found.poses {
        let (x, y, yaw) = (pose.x, pose.y, pose.yaw);
        check_pose(found.topic, pose.at.index, x, y, yaw)
            .map_err(|p| error(Some(pose.at.file), p))?;
        stream.unstamped += u64::from(!pose.at.stamped);
        stream
            .rows
            .push([seconds_since(base, pose.at.ns), x, y, yaw]);
    }
    if let Some(dropped) = found.dropped {
        let (from, to) = dropped.span_ns;
        warnings.push(format!(
            "{spec}: {} of {} pose(s) dropped: their time is outside the span of {} ({:.3} … {:.3} s), \
             which is not extrapolated",
            dropped.count,
            found.candidates,
            dropped.link,
            seconds_since(base, from),
            seconds_since(base, to),
        ));
    }
    Ok(())
}

/// `ns` in seconds after `base`.
pub(crate) fn seconds_since(base: u64, ns: u64) -> f64 {
    (i128::from(ns) - i128::from(base)) as f64 * 1e-9
}

/// Refuses a pose that is not finite or far from the origin (a unit error, a broken tracker).
/// Inlined with the words kept out of line: it runs for every pose of a bag.
#[inline]
pub(crate) fn check_pose(
    topic: &str,
    index: u64,
    x: f64,
    y: f64,
    yaw: f64,
) -> Result<(), BagProblem> {
    if x.is_finite() && y.is_finite() && yaw.is_finite() && x.abs().max(y.abs()) <= MAX_POSITION_M {
        return Ok(());
    }
    Err(bad_pose(topic, index, x, y, yaw))
}

#[cold]
#[inline(never)]
fn bad_pose(topic: &str, index: u64, x: f64, y: f64, yaw: f64) -> BagProblem {
    let why = match [x, y, yaw].iter().find(|v| !v.is_finite()) {
        Some(v) => format!("a pose value is {v}, expected a finite number"),
        None => format!("position ({x}, {y}) m, expected within {MAX_POSITION_M} m of the origin"),
    };
    BagProblem::BadValue {
        topic: topic.to_owned(),
        index,
        why,
    }
}

/// The pass over one file of a bag for the pusher's and the object's poses.
struct PoseVisitor<'a, 'spec> {
    streams: &'a mut [Stream<'spec>; 2],
    transforms: &'a mut Transforms,
    base: &'a mut Option<u64>,
    /// What each channel is read for, decided once, when it is declared.
    roles: HashMap<u16, Role>,
    /// Whether `/tf_static` is read: only when a child frame is asked for, since then it may hold
    /// links of its tree.
    wants_tree: bool,
    file_number: usize,
    /// The camera topics asked for, and their frames as found (`None` until the topic is seen as a
    /// camera).
    camera_topics: &'a [String],
    cameras: &'a mut Vec<Option<FoundCamera>>,
    progress: &'a dyn Progress,
}

impl Visitor for PoseVisitor<'_, '_> {
    fn want(&mut self, channel_id: u16, channel: &ChannelInfo) -> Want {
        if let Some(slot) = self.camera_topics.iter().position(|t| *t == channel.topic)
            && let Some(kind) =
                ImageKind::from_schema(&channel.type_name).filter(|_| channel.encoding == "cdr")
        {
            self.cameras[slot].get_or_insert_with(|| FoundCamera::new(channel.topic.clone(), kind));
            self.roles.insert(channel_id, Role::Camera(slot));
            return Want::Head(image_msg::STAMP_BYTES);
        }
        let role = (|| {
            let kind = PoseType::for_channel(&channel.encoding, &channel.type_name)?;
            let feeds = self
                .streams
                .each_ref()
                .map(|s| s.spec.topic == channel.topic);
            if kind == PoseType::TfMessage {
                let keep = feeds.contains(&true) || (self.wants_tree && channel.topic == TF_STATIC);
                return keep.then(|| Role::Tf(feeds, self.transforms.slot(&channel.topic)));
            }
            feeds.contains(&true).then_some(Role::Poses(feeds, kind))
        })();
        match role {
            Some(role) => {
                self.roles.insert(channel_id, role);
                Want::Payload
            }
            None => Want::Nothing,
        }
    }

    fn progress(&mut self, bytes: u64) -> Result<(), BagProblem> {
        self.progress.advance(bytes);
        if self.progress.is_cancelled() {
            return Err(BagProblem::Cancelled);
        }
        Ok(())
    }

    fn message(&mut self, visit: Visit<'_>) -> Result<(), BagProblem> {
        match self.roles.get(&visit.channel_id).copied() {
            None => Ok(()),
            Some(Role::Camera(slot)) => {
                if let Some(camera) = &mut self.cameras[slot] {
                    camera.note(
                        visit.data,
                        visit.log_time,
                        self.file_number as u32,
                        visit.at,
                    );
                }
                Ok(())
            }
            Some(Role::Poses(feeds, kind)) => read_message(
                self.streams,
                feeds,
                kind,
                visit.channel,
                visit.log_time,
                visit.data,
                self.base,
            ),
            Some(Role::Tf(feeds, slot)) => {
                let payload = visit.data;
                let streams = &*self.streams;
                let frames = [0, 1].map(|s| {
                    feeds[s]
                        .then_some(streams[s].spec.child_frame.as_deref())
                        .flatten()
                });
                let firsts = (self.transforms).record(
                    slot,
                    self.file_number,
                    visit.log_time,
                    payload,
                    frames,
                )?;
                if (0..2).any(|s| feeds[s] && frames[s].is_none()) {
                    return Err(need_child_frame(&visit.channel.topic, payload));
                }
                for ns in firsts.into_iter().flatten() {
                    self.base.get_or_insert(ns);
                }
                Ok(())
            }
        }
    }
}

/// Reads one message of a single-pose channel that feeds the streams flagged in `feeds` (both, when
/// the pusher and the object are one topic).
fn read_message(
    streams: &mut [Stream; 2],
    feeds: [bool; 2],
    kind: PoseType,
    channel: &ChannelInfo,
    log_time: u64,
    payload: &[u8],
    base: &mut Option<u64>,
) -> Result<(), BagProblem> {
    let index = streams[usize::from(!feeds[0])].index;
    for (stream, _) in streams.iter_mut().zip(feeds).filter(|(_, f)| *f) {
        stream.index += 1;
    }
    let pose = message::decode(kind, payload).map_err(|why| BagProblem::Decode {
        topic: channel.topic.clone(),
        index,
        type_name: kind.name(),
        why,
    })?;
    for (stream, _) in streams.iter_mut().zip(feeds).filter(|(_, f)| *f) {
        let ns = if pose.stamp_ns == 0 {
            stream.unstamped += 1;
            log_time
        } else {
            pose.stamp_ns
        };
        let base = *base.get_or_insert(ns);
        check_pose(&channel.topic, index, pose.x, pose.y, pose.yaw)?;
        stream
            .rows
            .push([seconds_since(base, ns), pose.x, pose.y, pose.yaw]);
    }
    Ok(())
}
