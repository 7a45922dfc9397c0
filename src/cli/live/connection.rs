//! Connecting to the robot's server, the first time and again after it went away: wait for the two
//! topics to be advertised, bind them **by topic name** (a server that restarts may number its
//! channels differently) and subscribe to every channel. The first connection fails at once with
//! the reason (a wrong address should not wait); a lost one is retried with backoff until it
//! comes back or the session ends.

use std::time::{Duration, Instant};

use anyhow::anyhow;
use pushlab_core::live::{LiveClient, LiveEvent};

use super::watched::Watched;
use crate::cli::exit::Failure;

/// How long to wait for the server, and at most between two looks at Ctrl-C.
pub(super) const READ_TIMEOUT: Duration = Duration::from_millis(100);
/// How long the topics asked for may take to be advertised.
const ADVERTISE_WAIT: Duration = Duration::from_secs(5);
/// The first wait before connecting again, doubled after each failed attempt up to the longest.
const FIRST_RETRY: Duration = Duration::from_millis(250);
const LONGEST_RETRY: Duration = Duration::from_secs(4);

/// A connection with both topics bound and every channel subscribed.
pub(super) struct Connected {
    pub(super) client: LiveClient,
    /// The server's name, if it said one.
    pub(super) server: Option<String>,
}

impl Connected {
    /// Connects to `url` and binds `watched` to the channels of their topics; `stop` is asked while
    /// waiting for them to be advertised.
    pub(super) fn open(
        url: &str,
        watched: &mut [Watched; 2],
        stop: &dyn Fn() -> bool,
    ) -> Result<Self, Failure> {
        let mut client =
            LiveClient::connect(url, READ_TIMEOUT).map_err(|e| Failure::Failed(e.into()))?;
        let asked = Instant::now();
        let mut server = None;
        while watched
            .iter()
            .any(|w| client.channel_of(&w.topic).is_none())
            && asked.elapsed() < ADVERTISE_WAIT
            && !stop()
        {
            if let Some(LiveEvent::ServerInfo { name }) =
                client.next_event().map_err(|e| Failure::Failed(e.into()))?
            {
                server = Some(name);
            }
        }
        for w in watched.iter_mut() {
            let channel = client.channel_of(&w.topic).cloned().ok_or_else(|| {
                let topics: Vec<String> = (client.channels())
                    .map(|c| format!("{} ({})", c.topic, c.schema_name))
                    .collect();
                Failure::Failed(anyhow!(
                    "{url}: no topic {} advertised within {} s; the server's topics: {}",
                    w.topic,
                    ADVERTISE_WAIT.as_secs(),
                    if topics.is_empty() {
                        "none".to_owned()
                    } else {
                        topics.join(", ")
                    }
                ))
            })?;
            w.bind(&channel)
                .map_err(|why| Failure::Usage(anyhow!("--{} {}: {why}", w.role, w.topic)))?;
        }
        let ids: Vec<u64> = client.channels().map(|c| c.id).collect();
        for id in ids {
            client
                .subscribe(id)
                .map_err(|e| Failure::Failed(e.into()))?;
        }
        Ok(Self { client, server })
    }

    /// Connects again after the connection was lost, waiting longer after each failed attempt,
    /// until it succeeds or `stop` says the session is over (`Ok(None)`). A topic the server no
    /// longer has is one more failed attempt; a topic of a type that cannot be read ends it.
    pub(super) fn reopen(
        url: &str,
        watched: &mut [Watched; 2],
        stop: &dyn Fn() -> bool,
    ) -> Result<Option<(Self, usize)>, Failure> {
        let mut wait = FIRST_RETRY;
        let mut attempts = 0;
        loop {
            let until = Instant::now() + wait;
            while Instant::now() < until {
                if stop() {
                    return Ok(None);
                }
                std::thread::sleep(Duration::from_millis(20));
            }
            attempts += 1;
            match Self::open(url, watched, stop) {
                Ok(connected) => return Ok(Some((connected, attempts))),
                Err(Failure::Usage(e)) => return Err(Failure::Usage(e)),
                Err(_) if stop() => return Ok(None),
                Err(_) => wait = (wait * 2).min(LONGEST_RETRY),
            }
        }
    }
}
