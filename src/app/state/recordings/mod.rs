//! The recordings open: the sets, their loads on workers, which one is shown (`session`), and the
//! browser's table of them (`browser`). Where they come from is `sources`.

pub mod browser;
pub mod session;
