//! Live input: a robot pushing now, read from a Foxglove WebSocket server (the Foxglove SDK's,
//! foxglove_bridge for ROS 1 and ROS 2), as the paper's setting has it — learning while the robot
//! pushes. The protocol's messages ([`protocol`]), a client ([`client`], not in a browser tab: a
//! page has no sockets of this kind), the pose in each message ([`pose`], through the bag reader's
//! decoders, so that a live session and its recording read the same numbers), the MCAP file
//! every message received is written to ([`recorder`]), a session with both streams followed by
//! topic name through reconnects ([`session`], [`followed`]: what the CLI and the app run), and learning as the frames arrive: the two
//! streams on the bag import's grid ([`grid`]) learned from by the core online run ([`learner`]),
//! so that the session and the replay of its recording agree to the bit. A controller driving the
//! robot sends the pusher's target back by client publish ([`command`]).

#[cfg(not(target_arch = "wasm32"))]
pub mod client;
#[cfg(not(target_arch = "wasm32"))]
pub mod command;
pub mod followed;
pub mod grid;
pub mod learner;
pub mod pose;
pub mod protocol;
#[cfg(not(target_arch = "wasm32"))]
pub mod recorder;
#[cfg(not(target_arch = "wasm32"))]
pub mod session;
pub mod tf_chain;

#[cfg(not(target_arch = "wasm32"))]
pub use self::client::{LiveClient, LiveError, LiveEvent, ServerOffers};
#[cfg(not(target_arch = "wasm32"))]
pub use self::command::{CommandEncoding, CommandRefused, CommandTopic};
pub use self::followed::{Followed, Lag};
pub use self::grid::{LiveGrid, Refused, Stream};
pub use self::learner::{AheadScore, LiveLearner, RefusedCounts};
pub use self::pose::PoseReading;
pub use self::protocol::{Channel, SUBPROTOCOLS};
#[cfg(not(target_arch = "wasm32"))]
pub use self::recorder::{RecordError, Recorded, Recorder};
#[cfg(not(target_arch = "wasm32"))]
pub use self::session::{LiveSession, SessionError, SessionEvent, decode_live_image, list_topics};
