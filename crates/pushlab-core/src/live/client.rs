//! A Foxglove WebSocket client over `tungstenite`, blocking, on the caller's thread: connect
//! offering both subprotocols, keep the channels the server advertises (at any time), subscribe,
//! and hand each message over with its channel. Reads wait at most the read timeout given, so that
//! a caller's loop can check for Cancel between two messages. The `foxglove` crate's own client is
//! test-only; this one is written from the spec (see [`super::protocol`]).

use std::collections::BTreeMap;
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use tungstenite::client::IntoClientRequest;
use tungstenite::http::HeaderValue;
use tungstenite::{Message, WebSocket};

use super::protocol::{self, Channel, ClientChannel, SUBPROTOCOLS, ServerBinary, ServerText};

/// Why a live connection failed; each names the server's address.
#[derive(Debug, thiserror::Error)]
pub enum LiveError {
    /// The address is not a `ws://host:port` one, or nothing answers there.
    #[error("{url}: cannot connect: {why}")]
    Connect { url: String, why: String },
    /// Something answered, but not as a Foxglove WebSocket server.
    #[error(
        "{url}: not a Foxglove WebSocket server: {why} (pushlab offers the subprotocols {})",
        SUBPROTOCOLS.join(", ")
    )]
    Handshake { url: String, why: String },
    /// A message that breaks the protocol.
    #[error("{url}: {why}")]
    Protocol { url: String, why: String },
    /// The server closed the connection, or it broke.
    #[error("{url}: the connection ended: {why}")]
    Closed { url: String, why: String },
}

/// What the server said, one message at a time.
#[derive(Clone, Debug, PartialEq)]
pub enum LiveEvent {
    /// The server's name (first, on connecting).
    ServerInfo { name: String },
    /// Channels that came (already kept in [`LiveClient::channels`]).
    Advertised(Vec<Channel>),
    /// Channels that went, by id (their subscriptions ended with them).
    Unadvertised(Vec<u64>),
    /// A message for the user: level 0 info, 1 warning, 2 error.
    Status { level: u8, message: String },
    /// A message on a subscribed channel, with the server's log time (nanoseconds).
    Message {
        channel: u64,
        log_time_ns: u64,
        payload: Vec<u8>,
    },
}

/// A connection to one server.
pub struct LiveClient {
    url: String,
    socket: WebSocket<TcpStream>,
    subprotocol: String,
    channels: BTreeMap<u64, Channel>,
    /// Subscription id → channel id.
    subscriptions: BTreeMap<u32, u64>,
    next_subscription: u32,
    /// What the server's `serverInfo` said it can do and which message encodings it takes from
    /// clients (`None` until it came).
    offers: Option<ServerOffers>,
}

/// What a server's `serverInfo` says it supports.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ServerOffers {
    pub capabilities: Vec<String>,
    /// Message encodings the server takes from a client that publishes.
    pub supported_encodings: Vec<String>,
}

impl LiveClient {
    /// Connects to `url` (`ws://host:port`), waiting at most `timeout` for the connection and for
    /// each read after it.
    pub fn connect(url: &str, timeout: Duration) -> Result<Self, LiveError> {
        let connect = |why: String| LiveError::Connect {
            url: url.to_owned(),
            why,
        };
        let mut request = url
            .into_client_request()
            .map_err(|e| connect(format!("{e}; expected ws://HOST:PORT")))?;
        if request.uri().scheme_str() != Some("ws") {
            return Err(connect(
                "expected ws://HOST:PORT (wss:// is not supported)".to_owned(),
            ));
        }
        let host = request.uri().host().unwrap_or_default().to_owned();
        let port = request.uri().port_u16().unwrap_or(80);
        let offered =
            HeaderValue::from_str(&SUBPROTOCOLS.join(", ")).map_err(|e| connect(e.to_string()))?;
        request
            .headers_mut()
            .insert("Sec-WebSocket-Protocol", offered);
        let address = (host.as_str(), port)
            .to_socket_addrs()
            .map_err(|e| connect(format!("cannot resolve {host}: {e}")))?
            .next()
            .ok_or_else(|| connect(format!("{host} has no address")))?;
        let stream =
            TcpStream::connect_timeout(&address, timeout).map_err(|e| connect(e.to_string()))?;
        let setup = stream
            .set_read_timeout(Some(timeout))
            .and_then(|()| stream.set_write_timeout(Some(timeout)))
            .and_then(|()| stream.set_nodelay(true));
        setup.map_err(|e| connect(e.to_string()))?;
        let (socket, response) =
            tungstenite::client::client(request, stream).map_err(|e| LiveError::Handshake {
                url: url.to_owned(),
                why: e.to_string(),
            })?;
        let subprotocol = (response.headers().get("Sec-WebSocket-Protocol"))
            .and_then(|v| v.to_str().ok())
            .filter(|chosen| SUBPROTOCOLS.contains(chosen))
            .ok_or_else(|| LiveError::Handshake {
                url: url.to_owned(),
                why: "it chose none of the subprotocols offered".to_owned(),
            })?
            .to_owned();
        Ok(Self {
            url: url.to_owned(),
            socket,
            subprotocol,
            channels: BTreeMap::new(),
            subscriptions: BTreeMap::new(),
            next_subscription: 1,
            offers: None,
        })
    }

    /// How long a read waits at most from now on (a controller reads more often than a viewer).
    pub fn set_read_timeout(&mut self, timeout: Duration) -> Result<(), LiveError> {
        (self.socket.get_ref().set_read_timeout(Some(timeout)))
            .map_err(|e| self.closed(e.to_string()))
    }

    /// The server's address, as given.
    pub fn url(&self) -> &str {
        &self.url
    }

    /// The subprotocol the server chose.
    pub fn subprotocol(&self) -> &str {
        &self.subprotocol
    }

    /// The channels advertised and not withdrawn, by id.
    pub fn channels(&self) -> impl Iterator<Item = &Channel> {
        self.channels.values()
    }

    /// An advertised channel by its id (a message's channel).
    pub fn channel(&self, id: u64) -> Option<&Channel> {
        self.channels.get(&id)
    }

    /// The first advertised channel of a topic.
    pub fn channel_of(&self, topic: &str) -> Option<&Channel> {
        self.channels.values().find(|c| c.topic == topic)
    }

    /// What the server said it supports, once its `serverInfo` came (the first message).
    pub fn offers(&self) -> Option<&ServerOffers> {
        self.offers.as_ref()
    }

    /// Advertises a channel of the client's own, to publish on (the server must offer
    /// [`protocol::CLIENT_PUBLISH`]: the caller checks [`Self::offers`]).
    pub fn advertise(&mut self, channel: &ClientChannel) -> Result<(), LiveError> {
        self.send(protocol::client_advertise(std::slice::from_ref(channel)))
    }

    /// Publishes a message on a channel the client advertised.
    pub fn publish(&mut self, channel: u32, payload: &[u8]) -> Result<(), LiveError> {
        let bytes = protocol::client_message_data(channel, payload);
        self.socket
            .send(Message::binary(bytes))
            .map_err(|e| self.closed(e.to_string()))
    }

    /// Subscribes to a channel; its messages then come as [`LiveEvent::Message`].
    pub fn subscribe(&mut self, channel: u64) -> Result<(), LiveError> {
        if self.subscriptions.values().any(|&c| c == channel) {
            return Ok(());
        }
        let id = self.next_subscription;
        self.next_subscription += 1;
        self.send(protocol::subscribe(&[(id, channel)]))?;
        self.subscriptions.insert(id, channel);
        Ok(())
    }

    /// The next event, or `None` when nothing came within the read timeout.
    pub fn next_event(&mut self) -> Result<Option<LiveEvent>, LiveError> {
        loop {
            acknowledge_at_once(self.socket.get_ref());
            let message = match self.socket.read() {
                Ok(message) => message,
                Err(tungstenite::Error::Io(e))
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) =>
                {
                    return Ok(None);
                }
                Err(e) => return Err(self.closed(e.to_string())),
            };
            let event = match message {
                Message::Text(text) => self.on_text(text.as_str())?,
                Message::Binary(bytes) => self.on_binary(&bytes)?,
                Message::Close(frame) => {
                    let why = frame.map_or("closed".to_owned(), |f| f.reason.to_string());
                    return Err(self.closed(why));
                }
                Message::Ping(_) | Message::Pong(_) | Message::Frame(_) => None,
            };
            if event.is_some() {
                return Ok(event);
            }
        }
    }

    /// Closes the connection politely.
    pub fn close(mut self) {
        let _ = self.socket.close(None);
        let _ = self.socket.flush();
    }

    fn on_text(&mut self, text: &str) -> Result<Option<LiveEvent>, LiveError> {
        let message = protocol::parse_text(text).map_err(|why| self.protocol(why))?;
        Ok(match message {
            ServerText::ServerInfo {
                name,
                capabilities,
                supported_encodings,
                ..
            } => {
                self.offers = Some(ServerOffers {
                    capabilities,
                    supported_encodings,
                });
                Some(LiveEvent::ServerInfo { name })
            }
            ServerText::Advertise { channels } => {
                for c in &channels {
                    self.channels.insert(c.id, c.clone());
                }
                Some(LiveEvent::Advertised(channels))
            }
            ServerText::Unadvertise { channel_ids } => {
                for id in &channel_ids {
                    self.channels.remove(id);
                }
                self.subscriptions.retain(|_, c| !channel_ids.contains(c));
                Some(LiveEvent::Unadvertised(channel_ids))
            }
            ServerText::Status { level, message } => Some(LiveEvent::Status { level, message }),
            ServerText::Other => None,
        })
    }

    fn on_binary(&mut self, bytes: &[u8]) -> Result<Option<LiveEvent>, LiveError> {
        let message = protocol::parse_binary(bytes).map_err(|why| self.protocol(why))?;
        Ok(match message {
            ServerBinary::MessageData {
                subscription,
                log_time_ns,
                payload,
            } => (self.subscriptions.get(&subscription)).map(|&channel| LiveEvent::Message {
                channel,
                log_time_ns,
                payload: payload.to_vec(),
            }),
            ServerBinary::Time { .. } | ServerBinary::Other { .. } => None,
        })
    }

    fn send(&mut self, text: String) -> Result<(), LiveError> {
        self.socket
            .send(Message::text(text))
            .map_err(|e| self.closed(e.to_string()))
    }

    fn protocol(&self, why: String) -> LiveError {
        LiveError::Protocol {
            url: self.url.clone(),
            why,
        }
    }

    fn closed(&self, why: String) -> LiveError {
        LiveError::Closed {
            url: self.url.clone(),
            why,
        }
    }
}

/// Asks the kernel to acknowledge what arrives at once rather than after its delayed-ACK timer.
/// A server that leaves Nagle's algorithm on (the Foxglove SDK's does not set TCP_NODELAY) holds a
/// small message back until the previous one is acknowledged: with delayed ACKs, tens of
/// milliseconds at a 1 kHz pose stream. The mode is not sticky (the kernel leaves it on its own), so
/// it is asked for before every read: one system call per message. Elsewhere than Linux, nothing.
fn acknowledge_at_once(stream: &TcpStream) {
    #[cfg(target_os = "linux")]
    {
        // A socket that refuses is read as before, with the kernel's delayed ACKs.
        let _ = socket2::SockRef::from(stream).set_tcp_quickack(true);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = stream;
}
