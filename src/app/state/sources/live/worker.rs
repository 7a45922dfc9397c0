//! The live session's worker thread (desktop only: a page has neither threads nor TCP sockets):
//! the core's [`LiveSession`] read message by message, both pose streams put on the grid, and what
//! came handed to the UI through the [`WorkerLink`]'s inbox.

use std::collections::BTreeMap;
use std::sync::Arc;

use pushlab_core::live::{LiveGrid, LiveSession, SessionEvent, decode_live_image};
use pushlab_core::recording::bag::ImageKind;

use super::commanding::Commanding;
use crate::app::state::sources::live::{Gap, Link, LiveChoice, LiveImage, WorkerLink};
use crate::app::state::sources::live_drive::DriveSetup;

/// Runs a session with `choice` on a grid at `rate_hz` until the link is stopped or the session
/// fails, driving the robot as `drive` says if it is given; says how it ended in the inbox.
pub fn run(choice: &LiveChoice, rate_hz: f64, drive: Option<&DriveSetup>, link: &WorkerLink) {
    let stop = || link.stopped();
    let record = (!choice.record.as_os_str().is_empty()).then_some(choice.record.as_path());
    let mut session =
        match LiveSession::open(&choice.url, &choice.pusher, &choice.object, record, &stop) {
            Ok(session) => session,
            Err(e) => {
                link.with(|inbox| {
                    inbox.latest.link = Link::Ended {
                        error: Some(e.to_string()),
                        recorded: None,
                    }
                });
                return;
            }
        };
    link.with(|inbox| {
        inbox.latest.link = Link::Connected {
            server: session.server().unwrap_or("unnamed server").to_owned(),
        }
    });
    session.show_images();
    let mut commanding = match drive.map(|setup| Commanding::open(&mut session, setup)) {
        Some(Ok(commanding)) => Some(commanding),
        Some(Err(why)) => {
            let status = Commanding::refused(&why);
            link.with(|inbox| {
                inbox.handed.said.extend(status.refused.clone());
                inbox.latest.drive = Some(status);
            });
            None
        }
        None => None,
    };
    // The newest camera message of each topic not yet decoded: decoded only once the UI took the
    // picture before it, so a camera faster than the window costs one decode per picture shown.
    let mut pending: BTreeMap<String, (ImageKind, Vec<u8>)> = BTreeMap::new();
    let mut shown: BTreeMap<String, u64> = BTreeMap::new();
    let mut grid = LiveGrid::new(rate_hz);
    let (mut handed, mut refused, mut said_full) = (0usize, 0usize, false);
    let mut error = None;
    // A reconnect waiting for its first frames: the frame handed last before it, and how long.
    let mut open_gap: Option<(usize, f64)> = None;
    while !stop() {
        let event = match session.next(&stop) {
            Ok(event) => event,
            Err(e) => {
                error = Some(e.to_string());
                break;
            }
        };
        let mut said = None;
        let mut new_link = None;
        match event {
            Some(SessionEvent::Pose {
                stream,
                pose,
                log_time_ns,
            }) => match grid.push(stream, &pose, log_time_ns) {
                Ok(()) => {
                    if let Some(c) = commanding.as_mut() {
                        c.take(stream, &pose);
                    }
                }
                Err(why) => {
                    refused += 1;
                    if refused == 1 {
                        said = Some(format!(
                            "a {} pose left out: {why} (every such pose after it is counted)",
                            stream.name()
                        ));
                    }
                }
            },
            Some(SessionEvent::Image {
                topic,
                kind,
                payload,
                ..
            }) => {
                let replaced = pending.insert(topic.clone(), (kind, payload));
                // The one before was never shown: dropped from the display (it is recorded).
                let dropped = u64::from(replaced.is_some());
                link.with(|inbox| {
                    *inbox.latest.images_dropped.entry(topic).or_default() += dropped
                });
            }
            Some(SessionEvent::Said(what)) => said = Some(what),
            Some(SessionEvent::Lost(why)) => {
                said = Some(format!("{why}; connecting again"));
                new_link = Some(Link::Lost { why });
                if let Some(c) = commanding.as_mut() {
                    c.lost();
                }
            }
            Some(SessionEvent::Reconnected { after_s, attempts }) => {
                said = Some(format!(
                    "connected again to {} after {after_s:.1} s ({attempts} attempt(s)): a gap in the recording and in the push after frame {}",
                    choice.url,
                    handed.saturating_sub(1)
                ));
                open_gap = Some((handed, after_s));
                if let Some(Err(e)) = commanding.as_mut().map(|c| c.reconnected(&mut session)) {
                    error = Some(e.to_string());
                    break;
                }
                new_link = Some(Link::Connected {
                    server: session.server().unwrap_or("unnamed server").to_owned(),
                });
            }
            None => {}
        }
        let mut drive_said = Vec::new();
        if let Some(Err(e)) =
            (commanding.as_mut()).map(|c| c.tick(&mut session, link, &mut drive_said))
        {
            error = Some(e.to_string());
            break;
        }
        let frames = grid.take_frames();
        let before = handed;
        handed += frames.len();
        let gap = match open_gap {
            Some((from, away_s)) if handed > before => {
                open_gap = None;
                Some(Gap {
                    frames: from..handed,
                    away_s,
                })
            }
            _ => None,
        };
        if grid.is_full() && !said_full {
            said_full = true;
            said = Some(
                "the push reached the longest an import takes: no more frames (the recording goes on)"
                    .to_owned(),
            );
        }
        let taken: Vec<String> = link.with(|inbox| {
            (pending.keys())
                .filter(|topic| !inbox.handed.images.contains_key(*topic))
                .cloned()
                .collect()
        });
        for topic in taken {
            let Some((kind, payload)) = pending.remove(&topic) else {
                continue;
            };
            let number = shown.entry(topic.clone()).or_default();
            *number += 1;
            let picture = match decode_live_image(kind, &payload) {
                Ok((stamp_ns, image)) => LiveImage {
                    stamp_ns,
                    number: *number,
                    image: Ok(Arc::new(image)),
                },
                Err(why) => LiveImage {
                    stamp_ns: 0,
                    number: *number,
                    image: Err(why),
                },
            };
            link.with(|inbox| inbox.handed.images.insert(topic, picture));
        }
        let lag = session.followed().each_ref().map(|f| f.lag());
        let messages = session.messages();
        link.with(|inbox| {
            inbox.handed.frames.extend(frames);
            inbox.handed.said.extend(said);
            inbox.handed.said.extend(drive_said);
            inbox.handed.gaps.extend(gap);
            if let Some(l) = new_link {
                inbox.latest.link = l;
            }
            inbox.latest.messages = messages;
            inbox.latest.lag = lag;
            inbox.latest.refused = refused;
        });
    }
    if let Some(c) = commanding.as_mut() {
        c.finish(&mut session, link);
    }
    let recorded = match session.finish() {
        Ok(recorded) => recorded.map(|r| {
            format!(
                "recorded {} message(s) on {} channel(s) to {}",
                r.messages,
                r.channels,
                r.path.display()
            )
        }),
        Err(e) => {
            error.get_or_insert(e.to_string());
            None
        }
    };
    link.with(|inbox| inbox.latest.link = Link::Ended { error, recorded });
}
