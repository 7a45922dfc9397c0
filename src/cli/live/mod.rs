//! `pushlab live ws://HOST:PORT --pusher TOPIC --object TOPIC [--record OUT.mcap]`: connects to a
//! running robot's Foxglove WebSocket server (the Foxglove SDK's, foxglove_bridge), subscribes to
//! every channel it advertises (now and later), writes every message received to `--record` as it
//! arrives, and prints once a second what came: messages and their rate, and the pusher's and the
//! object's latest poses with how late they arrived (`--json`: one JSON object a line). Ctrl-C or
//! `--duration` ends it; the recording is then closed cleanly and opens with `pushlab validate` and
//! `pushlab import` like any bag. A server that goes away is connected to again ([`connection`]),
//! the topics followed by name.
//!
//! With `--setting`, θ is learned online as the frames arrive ([`learning`]): the line of each
//! second adds θ, its σ and the losses, and the recording imported at the same rate (`pushlab import
//! --rate`) gives `pushlab eval` the same θ to the bit.

mod connection;
mod learning;
mod watched;

use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use clap::Args;
use pushlab_core::live::{LiveEvent, Recorder, Stream};
use serde_json::json;

use self::connection::Connected;
use self::learning::{Learning, LearningArgs};
use self::watched::Watched;
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

fn now_ns() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_nanos()).unwrap_or(u64::MAX))
}

/// Runs `pushlab live`.
pub fn run(args: &LiveArgs) -> Result<(), Failure> {
    interrupt::cancel_flag();
    let mut recorder = match &args.record {
        Some(path) => Some(Recorder::create(path).map_err(|e| Failure::Failed(e.into()))?),
        None => None,
    };
    let mut learning = Learning::new(&args.learning)?;
    let mut watched = [
        Watched::new(Stream::Pusher, &args.pusher),
        Watched::new(Stream::Object, &args.object),
    ];
    let Connected { mut client, server } =
        Connected::open(&args.url, &mut watched, &interrupt::cancelled)?;
    println!(
        "connected to {} ({}, {}): {} channel(s){}",
        args.url,
        server.as_deref().unwrap_or("unnamed server"),
        client.subprotocol(),
        client.channels().count(),
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
    let (mut messages, mut since_line) = (0u64, 0u64);
    loop {
        if stop() {
            break;
        }
        match client.next_event() {
            Ok(Some(LiveEvent::Message {
                channel,
                log_time_ns,
                payload,
            })) => {
                messages += 1;
                since_line += 1;
                if let (Some(recorder), Some(c)) = (recorder.as_mut(), client.channel(channel)) {
                    recorder
                        .write(c, log_time_ns, &payload)
                        .map_err(|e| Failure::Failed(e.into()))?;
                }
                let now = now_ns();
                for w in watched.iter_mut().filter(|w| w.channel == Some(channel)) {
                    if let (Some(pose), Some(learning)) = (w.take(&payload, now), &mut learning) {
                        learning.take(w.stream, &pose, log_time_ns);
                    }
                }
                if let Some(learning) = &mut learning {
                    learning.learn();
                }
            }
            Ok(Some(LiveEvent::Advertised(channels))) => {
                for c in channels {
                    client
                        .subscribe(c.id)
                        .map_err(|e| Failure::Failed(e.into()))?;
                    // A topic advertised again (its node restarted) is followed on its new channel.
                    for w in watched.iter_mut().filter(|w| w.topic == c.topic) {
                        if w.channel != Some(c.id) {
                            match w.bind(&c) {
                                Ok(()) => eprintln!(
                                    "the server advertised the {} topic {} again: following it",
                                    w.role, w.topic
                                ),
                                Err(why) => eprintln!("warning: {} {}: {why}", w.role, w.topic),
                            }
                        }
                    }
                }
            }
            Ok(Some(LiveEvent::Unadvertised(ids))) => {
                for w in watched
                    .iter()
                    .filter(|w| w.channel.is_some_and(|c| ids.contains(&c)))
                {
                    eprintln!(
                        "warning: the server withdrew the {} topic {}",
                        w.role, w.topic
                    );
                }
            }
            Ok(Some(LiveEvent::Status { level, message })) => {
                let level = ["info", "warning", "error"]
                    .get(usize::from(level))
                    .unwrap_or(&"status");
                eprintln!("server {level}: {message}");
            }
            Ok(Some(LiveEvent::ServerInfo { .. }) | None) => {}
            Err(e) => {
                if stop() {
                    break;
                }
                let lost = Instant::now();
                eprintln!("warning: {e}; connecting again (Ctrl-C ends the session)");
                if let Some(recorder) = recorder.as_mut() {
                    recorder.flush().map_err(|e| Failure::Failed(e.into()))?;
                }
                let Some((connected, attempts)) =
                    Connected::reopen(&args.url, &mut watched, &stop)?
                else {
                    break;
                };
                client = connected.client;
                println!(
                    "reconnected to {} after {:.1} s ({attempts} attempt(s)): {} channel(s); a gap in the recording and in learning there (an import interpolates across it and says so; pushlab import --split-gap cuts the push there)",
                    args.url,
                    lost.elapsed().as_secs_f64(),
                    client.channels().count(),
                );
            }
        }
        let elapsed = started.elapsed();
        if elapsed >= next_line {
            next_line += Duration::from_secs(1);
            if let Some(recorder) = recorder.as_mut() {
                recorder.flush().map_err(|e| Failure::Failed(e.into()))?;
            }
            print_line(
                args.json,
                elapsed,
                messages,
                since_line,
                &watched,
                learning.as_mut(),
            );
            since_line = 0;
        }
    }
    print_line(
        args.json,
        started.elapsed(),
        messages,
        0,
        &watched,
        learning.as_mut(),
    );
    if let Some(recorder) = recorder {
        let recorded = recorder.finish().map_err(|e| Failure::Failed(e.into()))?;
        println!(
            "recorded {} message(s) on {} channel(s) to {}; open it with pushlab validate {} or pushlab import",
            recorded.messages,
            recorded.channels,
            recorded.path.display(),
            recorded.path.display()
        );
    }
    client.close();
    Ok(())
}

/// The line of one second: time, messages, rate, the two latest poses, and what learning holds.
fn print_line(
    json: bool,
    elapsed: Duration,
    messages: u64,
    in_second: u64,
    watched: &[Watched],
    learning: Option<&mut Learning>,
) {
    if json {
        let mut line = json!({
            "t": elapsed.as_secs_f64(),
            "messages": messages,
            "rate_hz": in_second,
            "pusher": watched[0].json(),
            "object": watched[1].json(),
        });
        if let Some(learning) = learning {
            line["learning"] = learning.json();
        }
        println!("{line}");
    } else {
        println!(
            "{:>7.1} s  {messages} messages ({in_second}/s)  {}  {}{}",
            elapsed.as_secs_f64(),
            watched[0].text(),
            watched[1].text(),
            learning
                .map(|l| format!("\n          {}", l.text()))
                .unwrap_or_default()
        );
    }
}
