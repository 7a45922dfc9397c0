//! Push it yourself: a mystery object whose centre of mass and `h` are hidden, pushed by a student
//! (a pointer dragging the pusher, or a push chosen on the object), simulated in real time by the
//! core's simulator, and learned as it is pushed by the same online run as every recording. What a
//! class needs to see a model find a hidden quantity from the pushes they choose.
//!
//! The pieces: [`mystery`] (the object and what is hidden, from a seed), [`pointer`] (a pointer's
//! path and the one rule the pusher follows it by), [`table`] (the pushes made, frame by frame:
//! the simulator's stepper), [`review`] (the score card of a reveal). Growing a push and learning
//! it is not here: the app grows a sandbox push on the path a live robot's push takes, and
//! `pushlab simulate --pointer-path` writes a push made here as a recording.

pub mod arrow;
pub mod mystery;
pub mod pointer;
pub mod review;
pub mod saved;
pub mod table;

pub use arrow::{push_drawn, push_of_shape};
pub use mystery::{Hidden, Mystery, MysteryError, MysteryObject};
pub use pointer::{PointerPath, PointerPathError, follow};
pub use review::{PushReview, ScoreCard, Scored, review_push};
pub use saved::SandboxSet;
pub use table::{MadePush, PushChoice, PushRefused, Sandbox, SandboxEvent, recorded_pushes};
