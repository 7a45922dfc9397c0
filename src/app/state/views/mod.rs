//! What the panels read across rooms: the browser's rows, pending proposals, the what-if rollout,
//! losses by label (`across`), and what several panels read each frame, computed once per change
//! (`frame_cache`).

pub(super) mod across;
pub(super) mod frame_cache;
