//! Every message a live session receives, written to an MCAP file as it arrives, so that nothing is
//! lost: the session can be replayed, labelled and trained on later like any bag. Each channel gets
//! its schema and channel records when first seen; messages keep the server's log time. Chunks are
//! ended every [`Recorder::flush`] (the caller's clock: once a second), so that a crash loses at
//! most the chunk being written and leaves a file the bag reader opens as cut short; [`Recorder::finish`]
//! (or dropping the recorder) writes the summary and the indexes. A file that exists is never
//! written over: it may be a user's recording.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::protocol::Channel;

/// Why a live session could not be recorded; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{}: already exists; pushlab does not write over a recording (choose a new name)", path.display())]
    Exists { path: PathBuf },
    #[error("{}: cannot write: {why}", path.display())]
    Write { path: PathBuf, why: String },
}

/// What a finished recording holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Recorded {
    pub path: PathBuf,
    pub channels: usize,
    pub messages: u64,
}

/// An MCAP file being written.
pub struct Recorder {
    path: PathBuf,
    writer: mcap::Writer<BufWriter<File>>,
    /// The server's channel id → the file's, with the topic it had: a server that restarts may give
    /// an id to another topic.
    by_id: BTreeMap<u64, (u16, String)>,
    /// (topic, encoding, schema name) → the file's channel: a topic seen again under a new id (the
    /// server restarted) goes on in the same channel of the file.
    channels: BTreeMap<(String, String, String), u16>,
    messages: u64,
}

impl Recorder {
    /// Creates the file at `path`, which must not exist.
    pub fn create(path: &Path) -> Result<Self, RecordError> {
        let fail = |why: String| RecordError::Write {
            path: path.to_path_buf(),
            why,
        };
        let file = File::create_new(path).map_err(|e| match e.kind() {
            std::io::ErrorKind::AlreadyExists => RecordError::Exists {
                path: path.to_path_buf(),
            },
            _ => fail(e.to_string()),
        })?;
        let writer = mcap::WriteOptions::new()
            .compression(None)
            .profile("ros2")
            .library(concat!("pushlab ", env!("CARGO_PKG_VERSION")))
            .create(BufWriter::new(file))
            .map_err(|e| fail(e.to_string()))?;
        Ok(Self {
            path: path.to_path_buf(),
            writer,
            by_id: BTreeMap::new(),
            channels: BTreeMap::new(),
            messages: 0,
        })
    }

    /// Writes a message received on `channel` (as advertised) at the server's `log_time_ns`; the
    /// channel's schema and channel records go first the first time it is seen.
    pub fn write(
        &mut self,
        channel: &Channel,
        log_time_ns: u64,
        payload: &[u8],
    ) -> Result<(), RecordError> {
        let id = match self.by_id.get(&channel.id) {
            Some((id, topic)) if *topic == channel.topic => *id,
            _ => {
                let key = (
                    channel.topic.clone(),
                    channel.encoding.clone(),
                    channel.schema_name.clone(),
                );
                let id = match self.channels.get(&key) {
                    Some(&id) => id,
                    None => {
                        let id = self.add_channel(channel)?;
                        self.channels.insert(key, id);
                        id
                    }
                };
                self.by_id.insert(channel.id, (id, channel.topic.clone()));
                id
            }
        };
        let header = mcap::records::MessageHeader {
            channel_id: id,
            sequence: (self.messages % u64::from(u32::MAX)) as u32,
            log_time: log_time_ns,
            publish_time: log_time_ns,
        };
        self.writer
            .write_to_known_channel(&header, payload)
            .map_err(|e| self.fail(e.to_string()))?;
        self.messages += 1;
        Ok(())
    }

    /// Ends the chunk being written and pushes it to the disk: what a crash after this keeps.
    pub fn flush(&mut self) -> Result<(), RecordError> {
        self.writer.flush().map_err(|e| self.fail(e.to_string()))
    }

    /// Messages written so far.
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the summary and the indexes, and closes the file.
    pub fn finish(mut self) -> Result<Recorded, RecordError> {
        self.writer.finish().map_err(|e| self.fail(e.to_string()))?;
        Ok(Recorded {
            path: self.path.clone(),
            channels: self.channels.len(),
            messages: self.messages,
        })
    }

    fn add_channel(&mut self, channel: &Channel) -> Result<u16, RecordError> {
        // A schema's encoding as MCAP's registry names it; older servers leave it out of advertise.
        let encoding = match (&channel.schema_encoding, channel.encoding.as_str()) {
            (Some(e), _) => e.clone(),
            (None, "cdr") => "ros2msg".to_owned(),
            (None, "json") => "jsonschema".to_owned(),
            (None, "ros1") => "ros1msg".to_owned(),
            (None, _) => String::new(),
        };
        let schema = match channel.schema_name.is_empty() {
            true => 0,
            false => self
                .writer
                .add_schema(&channel.schema_name, &encoding, channel.schema.as_bytes())
                .map_err(|e| self.fail(e.to_string()))?,
        };
        self.writer
            .add_channel(schema, &channel.topic, &channel.encoding, &BTreeMap::new())
            .map_err(|e| self.fail(e.to_string()))
    }

    fn fail(&self, why: String) -> RecordError {
        RecordError::Write {
            path: self.path.clone(),
            why,
        }
    }
}
