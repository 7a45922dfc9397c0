//! Sending on a live session: the pusher's target to a robot's server by client publish. The
//! command topic is agreed with the server once ([`CommandTopic::agree`]: refused by name unless
//! it offers client publish) and advertised again whenever the session connects again, since a
//! server forgets a client's channels with the client. Every message sent goes into the session's
//! recording beside what was received, so that a session replays both ways. Whether a target
//! may be sent at all is not decided here: the controller's safety gate decides
//! (`control::drive`).

use nalgebra::Point2;

use super::{LiveSession, SessionError, SessionEvent, unix_now_ns};
use crate::live::command::{CommandEncoding, CommandTopic};

/// The client's id of its command channel (a client numbers its own channels).
const COMMAND_CHANNEL: u32 = 1;
/// The command channel's id in the recording's bookkeeping, apart from any id a server gives.
const RECORDED_COMMAND_ID: u64 = 1 << 48;

impl LiveSession {
    /// Agrees the command topic `topic` (targets stamped in `frame_id`) with the server and
    /// advertises it; the encoding agreed. Refused, by name, by a server that does not offer
    /// client publish or takes neither CDR nor JSON.
    pub fn advertise_command(
        &mut self,
        topic: &str,
        frame_id: &str,
    ) -> Result<CommandEncoding, SessionError> {
        let client = self
            .client
            .as_mut()
            .ok_or_else(|| crate::live::LiveError::Closed {
                url: self.url.clone(),
                why: "not connected".to_owned(),
            })?;
        let command = CommandTopic::agree(&self.url, topic, frame_id, client.offers())?;
        client.advertise(&command.client_channel(COMMAND_CHANNEL))?;
        let encoding = command.encoding();
        self.command = Some(command);
        Ok(encoding)
    }

    /// Sends the pusher's target: `true` when sent, `false` when the connection is lost (the loss
    /// is handed out by the next [`LiveSession::next`], which connects again). Nothing is sent
    /// before [`LiveSession::advertise_command`].
    pub fn send_command(&mut self, target: Point2<f64>) -> Result<bool, SessionError> {
        let (Some(client), Some(command)) = (self.client.as_mut(), self.command.as_ref()) else {
            return Ok(false);
        };
        let stamp = unix_now_ns();
        let payload = command.encode(stamp, target);
        if let Err(e) = client.publish(COMMAND_CHANNEL, &payload) {
            if let Some(recorder) = self.recorder.as_mut() {
                recorder.flush()?;
            }
            self.client = None;
            self.lost_at = Some(std::time::Instant::now());
            self.queued.push_back(SessionEvent::Lost(e.to_string()));
            return Ok(false);
        }
        if let Some(recorder) = self.recorder.as_mut() {
            recorder.write(
                &command.recorded_channel(RECORDED_COMMAND_ID),
                stamp,
                &payload,
            )?;
        }
        self.commands_sent += 1;
        Ok(true)
    }

    /// Commands sent so far.
    pub fn commands_sent(&self) -> u64 {
        self.commands_sent
    }

    /// The command topic agreed and advertised again on the new connection (after a reconnect):
    /// a server restarted may take another encoding, or refuse.
    pub(super) fn advertise_command_again(&mut self) -> Result<(), SessionError> {
        let (Some(client), Some(command)) = (self.client.as_mut(), self.command.as_ref()) else {
            return Ok(());
        };
        let again = CommandTopic::agree(
            &self.url,
            command.topic(),
            command.frame_id(),
            client.offers(),
        )?;
        client.advertise(&again.client_channel(COMMAND_CHANNEL))?;
        self.command = Some(again);
        Ok(())
    }
}
