//! Playback: the frame shown and what is drawn of it. The timeline (playing, speed, loop, the
//! frame), the scene's layers, the recording's whole path thinned for the scene, its cameras, and
//! every prediction of the frame shown. Nothing here learns or knows the other rooms: every other
//! room may read it.

pub mod cameras;
pub mod layers;
pub mod overview;
pub mod predictions;
pub mod timeline;
