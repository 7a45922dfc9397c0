//! `pushlab live ws://HOST:PORT --pusher TOPIC --object TOPIC [--record OUT.mcap]`: connects to a
//! running robot's Foxglove WebSocket server (the Foxglove SDK's, foxglove_bridge), subscribes to
//! every channel it advertises (now and later), writes every message received to `--record` as it
//! arrives, and prints once a second what came: messages and their rate, and the pusher's and the
//! object's latest poses with how late they arrived (`--json`: one JSON object a line). Ctrl-C or
//! `--duration` ends it; the recording is then closed cleanly and opens with `pushlab validate` and
//! `pushlab import` like any bag. A server that goes away is connected to again (the core's `live::session`, which the app runs too),
//! the topics followed by name.
//!
//! With `--setting`, θ is learned online as the frames arrive ([`learning`]): the line of each
//! second adds θ, its σ and the losses, and the recording imported at the same rate (`pushlab import
//! --rate`) gives `pushlab eval` the same θ to the bit.

mod learning;
mod shown;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::anyhow;
use clap::Args;
use pushlab_core::live::{LiveSession, SessionError, SessionEvent};
use serde_json::json;

use self::learning::{Learning, LearningArgs};
use super::exit::Failure;
use super::experiment::args::positive_real;
use super::interrupt;

/// Arguments of `pushlab live`.
#[derive(Debug, Args)]
pub struct LiveArgs {
    /// The server's address: ws://HOST:PORT (foxglove_bridge and the Foxglove SDK listen on 8765).
    pub url: String,
    /// The pusher's topic (TOPIC:CHILD_FRAME for a TFMessage topic such as /tf).
    #[arg(long, value_name = "TOPIC")]
    pub pusher: String,
    /// The object's topic (TOPIC:CHILD_FRAME for a TFMessage topic such as /tf).
    #[arg(long, value_name = "TOPIC")]
    pub object: String,
    /// Write every message received, on every channel, to this new MCAP file as it arrives.
    #[arg(long, value_name = "OUT.mcap")]
    pub record: Option<PathBuf>,
    /// Print one JSON object a second instead of a line of text.
    #[arg(long)]
    pub json: bool,
    /// Stop after this many seconds (else at Ctrl-C or when the server closes).
    #[arg(long, value_name = "SECONDS", value_parser = positive_real)]
    pub duration: Option<f64>,
    #[command(flatten)]
    pub learning: LearningArgs,
}

/// A session's error as the CLI says it: a topic that cannot be read is the command line's fault
/// (`pushlab live` and `pushlab control ws://…` both run a session).
pub(super) fn failure(error: SessionError) -> Failure {
    match error {
        SessionError::Unreadable { role, topic, why } => {
            Failure::Usage(anyhow!("--{role} {topic}: {why}"))
        }
        error => Failure::Failed(error.into()),
    }
}

/// Runs `pushlab live`.
pub fn run(args: &LiveArgs) -> Result<(), Failure> {
    interrupt::cancel_flag();
    let mut learning = Learning::new(&args.learning)?;
    let mut session = LiveSession::open(
        &args.url,
        &args.pusher,
        &args.object,
        args.record.as_deref(),
        &interrupt::cancelled,
    )
    .map_err(failure)?;
    println!(
        "connected to {} ({}, {}): {} channel(s){}",
        args.url,
        session.server().unwrap_or("unnamed server"),
        session.subprotocol().unwrap_or("?"),
        session.channels(),
        args.record
            .as_ref()
            .map(|p| format!(", recording to {}", p.display()))
            .unwrap_or_default()
    );

    let started = Instant::now();
    let stop = || {
        interrupt::cancelled()
            || args
                .duration
                .is_some_and(|d| started.elapsed().as_secs_f64() >= d)
    };
    let mut next_line = Duration::from_secs(1);
    let (mut line_messages, mut lost) = (0u64, None::<Instant>);
    while !stop() {
        match session.next(&stop).map_err(failure)? {
            Some(SessionEvent::Pose {
                stream,
                pose,
                log_time_ns,
            }) => {
                if let Some(learning) = &mut learning {
                    learning.take(stream, &pose, log_time_ns);
                    learning.learn();
                }
            }
            Some(SessionEvent::Said(what)) => eprintln!("warning: {what}"),
            Some(SessionEvent::Lost(why)) => {
                lost = Some(Instant::now());
                eprintln!("warning: {why}; connecting again (Ctrl-C ends the session)");
            }
            Some(SessionEvent::Reconnected { attempts, .. }) => println!(
                "reconnected to {} after {:.1} s ({attempts} attempt(s)): {} channel(s); a gap in the recording and in learning there (an import interpolates across it and says so; pushlab import --split-gap cuts the push there)",
                args.url,
                lost.take().map_or(0.0, |t| t.elapsed().as_secs_f64()),
                session.channels(),
            ),
            // Images are recorded, not shown, here (the session hands them out only when asked).
            Some(SessionEvent::Image { .. }) | None => {}
        }
        let elapsed = started.elapsed();
        if elapsed >= next_line {
            next_line += Duration::from_secs(1);
            let in_second = session.messages() - line_messages;
            line_messages = session.messages();
            print_line(args.json, elapsed, &session, in_second, learning.as_mut());
        }
    }
    print_line(args.json, started.elapsed(), &session, 0, learning.as_mut());
    if let Some(recorded) = session.finish().map_err(failure)? {
        println!(
            "recorded {} message(s) on {} channel(s) to {}; open it with pushlab validate {} or pushlab import",
            recorded.messages,
            recorded.channels,
            recorded.path.display(),
            recorded.path.display()
        );
    }
    Ok(())
}

/// The line of one second: time, messages, rate, the two latest poses, and what learning holds.
fn print_line(
    json: bool,
    elapsed: Duration,
    session: &LiveSession,
    in_second: u64,
    learning: Option<&mut Learning>,
) {
    let messages = session.messages();
    let [pusher, object] = session.followed();
    if json {
        let mut line = json!({
            "t": elapsed.as_secs_f64(),
            "messages": messages,
            "rate_hz": in_second,
            "pusher": shown::json(pusher),
            "object": shown::json(object),
        });
        if let Some(learning) = learning {
            line["learning"] = learning.json();
        }
        println!("{line}");
    } else {
        println!(
            "{:>7.1} s  {messages} messages ({in_second}/s)  {}  {}{}",
            elapsed.as_secs_f64(),
            shown::text(pusher),
            shown::text(object),
            learning
                .map(|l| format!("\n          {}", l.text()))
                .unwrap_or_default()
        );
    }
}
