//! Demos: the Demos menu's presets, the narration (`demo`) and starting one (`start`).

pub mod demo;
pub(super) mod start;
