//! Listing a bag's topics: type, encoding, message count, log-time span and, for a TF topic, the
//! child frames it carries — what `pushlab validate BAG` prints and the app's bag form offers.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::files::bag_files;
use super::mcap_file::{ChannelInfo, for_each_message};
use super::topic_info::TopicInfo;
use crate::recording::error::LoadError;
use crate::recording::read::read_file;

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
                self.infos.push(TopicInfo {
                    topic: channel.topic.clone(),
                    type_name: channel.type_name.clone(),
                    encoding: channel.encoding.clone(),
                    count: 0,
                    first_ns: 0,
                    last_ns: 0,
                    child_frames: Vec::new(),
                });
                self.infos.len() - 1
            }
        };
        &mut self.infos[index]
    }

    /// Counts one message of the channel's topic at `log_time`; returns the topic's entry.
    pub(super) fn note(&mut self, channel: &ChannelInfo, log_time: u64) -> &mut TopicInfo {
        let info = self.entry(channel);
        // The span starts at the first message, even when an earlier file of the bag listed the
        // channel without any (its 0 is not a time).
        if info.count == 0 {
            info.first_ns = log_time;
            info.last_ns = log_time;
        }
        info.count += 1;
        info.first_ns = info.first_ns.min(log_time);
        info.last_ns = info.last_ns.max(log_time);
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

    /// A channel of a file that carried no message on it: listed, with no messages.
    pub(super) fn add_silent(&mut self, channel: &ChannelInfo) {
        self.entry(channel);
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

/// Lists the topics of a bag with their types, message counts and log-time span.
pub fn topics(path: &Path) -> Result<Vec<TopicInfo>, LoadError> {
    topics_in(&bag_files(path)?, read_file)
}

/// Lists the topics of one `.mcap` file held in memory; `path` is only used in messages.
pub fn topics_bytes(bytes: &[u8], path: &Path) -> Result<Vec<TopicInfo>, LoadError> {
    topics_in(&[path.to_path_buf()], |_| Ok(bytes.to_vec()))
}

fn topics_in(
    files: &[PathBuf],
    mut load: impl FnMut(&Path) -> Result<Vec<u8>, LoadError>,
) -> Result<Vec<TopicInfo>, LoadError> {
    let mut table = TopicTable::default();
    for file in files {
        let bytes = load(file)?;
        let mut channels = HashMap::new();
        for_each_message(&bytes, &mut channels, |channel, _, log_time, payload| {
            table.note(channel, log_time).note_frames(payload);
            Ok(())
        })
        .map_err(|problem| LoadError::Bag {
            path: file.clone(),
            problem,
        })?;
        for channel in channels.values() {
            table.add_silent(channel);
        }
    }
    Ok(table.into_sorted())
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
        table.add_silent(&channel);
        for t in [3_000_000_000, 4_000_000_000, 5_000_000_000] {
            table.note(&channel, t);
        }
        let info = table.get("/object/pose").unwrap();
        assert_eq!(
            (info.count, info.first_ns, info.last_ns),
            (3, 3_000_000_000, 5_000_000_000)
        );
        assert_eq!(info.rate_hz(), 1.0);
    }
}
