//! Listing a bag's topics: type, encoding, message count, log-time span and, for a TF topic, the
//! child frames it carries — what `pushlab validate BAG` prints and the app's bag form offers.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::cdr::PoseType;
use super::error::BagError;
use super::files::{bag_files, read_file};
use super::image_msg::{ImageKind, describe};
use super::mcap::{ChannelInfo, ChannelStats, CutShort, Visit, Visitor, Want, read_messages};
use super::problem::BagProblem;
use super::topic_info::{BagListing, CameraInfo, TopicInfo};

/// Topics by name, accumulating over the files of a bag. Looked up by `&str` for every message of
/// a bag, so a topic's name is copied once, when it is first seen, not per message.
#[derive(Default)]
pub(super) struct TopicTable {
    /// In order of first appearance.
    infos: Vec<TopicInfo>,
    /// Index into `infos` by topic.
    by_topic: HashMap<String, usize>,
}

impl TopicTable {
    /// The topic's entry, made empty (no messages) the first time its channel is seen.
    fn entry(&mut self, channel: &ChannelInfo) -> &mut TopicInfo {
        let index = match self.by_topic.get(channel.topic.as_str()) {
            Some(&index) => index,
            None => {
                self.by_topic
                    .insert(channel.topic.clone(), self.infos.len());
                self.infos.push(empty_topic(channel));
                self.infos.len() - 1
            }
        };
        &mut self.infos[index]
    }

    /// Adds one file's messages of the channel's topic; returns the topic's entry.
    pub(super) fn add(&mut self, channel: &ChannelInfo, stats: &ChannelStats) -> &mut TopicInfo {
        let info = self.entry(channel);
        if stats.count > 0 {
            // The span starts at the first message, even when an earlier file of the bag listed
            // the channel without any (its 0 is not a time).
            if info.count == 0 {
                info.first_ns = stats.first;
                info.last_ns = stats.last;
            }
            info.count += stats.count;
            info.first_ns = info.first_ns.min(stats.first);
            info.last_ns = info.last_ns.max(stats.last);
        }
        info
    }

    /// A topic by name.
    pub(super) fn get(&self, topic: &str) -> Option<&TopicInfo> {
        self.by_topic.get(topic).map(|&index| &self.infos[index])
    }

    /// The topics, sorted by name.
    pub(super) fn into_sorted(mut self) -> Vec<TopicInfo> {
        self.infos.sort_by(|a, b| a.topic.cmp(&b.topic));
        self.infos
    }

    /// `"/a (type, N messages), /b (…)"` for error messages.
    pub(super) fn listing(&self) -> String {
        if self.infos.is_empty() {
            return "none".to_owned();
        }
        let mut sorted: Vec<&TopicInfo> = self.infos.iter().collect();
        sorted.sort_by(|a, b| a.topic.cmp(&b.topic));
        sorted
            .into_iter()
            .map(|t| format!("{} ({}, {} messages)", t.topic, t.type_name, t.count))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Lists the topics of a bag with their types, message counts and log-time span. Only the messages
/// of TF topics (for their child frames) and each camera's first frame (for its encoding and size)
/// are read; the counts come from the files' indexes (from reading a file through when it has
/// none: cut short).
pub fn topics(path: &Path) -> Result<BagListing, BagError> {
    topics_in(path, &bag_files(path)?, None)
}

/// Lists the topics of one `.mcap` file held in memory; `path` is only used in messages.
pub fn topics_bytes(bytes: &[u8], path: &Path) -> Result<BagListing, BagError> {
    topics_in(path, &[path.to_path_buf()], Some(bytes))
}

fn topics_in(path: &Path, files: &[PathBuf], bytes: Option<&[u8]>) -> Result<BagListing, BagError> {
    let mut table = TopicTable::default();
    let mut cut_short = Vec::new();
    for file in files {
        let mut details = Details::default();
        let read = read_file(file, bytes, |source| read_messages(source, &mut details))?;
        if let Some(cut) = read.cut_short {
            cut_short.push(cut_of(path, file, cut));
        }
        for (id, (channel, stats)) in &read.channels {
            let info = table.add(channel, stats);
            if let Some(found) = details.0.get(id) {
                for frame in &found.child_frames {
                    info.add_frame(frame);
                }
                if info.camera.is_none() {
                    info.camera.clone_from(&found.camera);
                }
            }
        }
    }
    Ok(BagListing {
        topics: table.into_sorted(),
        cut_short,
    })
}

/// A cut-short warning as said of the bag: of a rosbag2 folder's files, it names the one cut.
pub(super) fn cut_of(bag: &Path, file: &Path, cut: CutShort) -> String {
    match file.strip_prefix(bag) {
        Ok(inside) if !inside.as_os_str().is_empty() => format!("{}: {cut}", inside.display()),
        _ => cut.to_string(),
    }
}

/// A channel's topic, with no messages yet.
fn empty_topic(channel: &ChannelInfo) -> TopicInfo {
    TopicInfo {
        topic: channel.topic.clone(),
        type_name: channel.type_name.clone(),
        encoding: channel.encoding.clone(),
        count: 0,
        first_ns: 0,
        last_ns: 0,
        child_frames: Vec::new(),
        camera: None,
    }
}

/// What a listing reads of a file: the child frames of its TF topics, and the first frame of each
/// camera topic (its encoding and size).
#[derive(Default)]
struct Details(HashMap<u16, TopicInfo>);

/// Bytes of a camera message's start read for its encoding and size: the header, the format or
/// size fields, and a JPEG's frame header or a PNG's IHDR.
const CAMERA_HEAD: usize = 4096;

impl Visitor for Details {
    fn want(&mut self, _: u16, channel: &ChannelInfo) -> Want {
        if channel.encoding != "cdr" {
            return Want::Nothing;
        }
        if PoseType::from_schema(&channel.type_name) == Some(PoseType::TfMessage) {
            Want::Payload
        } else if ImageKind::from_schema(&channel.type_name).is_some() {
            Want::First(CAMERA_HEAD)
        } else {
            Want::Nothing
        }
    }

    fn message(&mut self, visit: Visit<'_>) -> Result<(), BagProblem> {
        let info = (self.0.entry(visit.channel_id)).or_insert_with(|| empty_topic(visit.channel));
        match ImageKind::from_schema(&visit.channel.type_name) {
            Some(kind) => {
                let (encoding, size) = describe(kind, visit.data);
                info.camera = Some(CameraInfo { encoding, size });
            }
            None => info.note_frames(visit.data),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn a_topic_silent_in_an_earlier_file_spans_from_its_first_message() {
        let channel = ChannelInfo {
            topic: "/object/pose".to_owned(),
            type_name: "geometry_msgs/msg/PoseStamped".to_owned(),
            encoding: "cdr".to_owned(),
        };
        let mut table = TopicTable::default();
        table.add(&channel, &ChannelStats::default());
        let stats = ChannelStats {
            count: 3,
            first: 3_000_000_000,
            last: 5_000_000_000,
        };
        table.add(&channel, &stats);
        let info = table.get("/object/pose").unwrap();
        assert_eq!(
            (info.count, info.first_ns, info.last_ns),
            (3, 3_000_000_000, 5_000_000_000)
        );
        assert_eq!(info.rate_hz(), 1.0);
    }
}
