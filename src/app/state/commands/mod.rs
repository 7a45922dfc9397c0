//! The state's commands carried out where they reach over several rooms: the session's, online
//! learning's, training's and the effects (`apply`), and the File menu's (`files`, with the video
//! export it starts and polls: `video_export`).

pub(super) mod apply;
pub(super) mod files;
pub mod video_export;
