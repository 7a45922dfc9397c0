//! The browser's shown rows kept between frames: which open recordings pass the filter, in the
//! sort's order, and the columns they have values in.
//!
//! Why: computing them reads every open recording's parameters, labels file and losses, formats a
//! name and a sort key for each and sorts them, where the table draws only the thirty rows in view:
//! with 5,000 recordings open, 2 ms of every frame in the `frame_playing_5k_recordings` benchmark
//! and 13 ms by the app's own meter (performance.md, "Many recordings open"). They are computed
//! again only when something they depend on changes (`ShownKey` in `browser.rs`); a frame then
//! builds the rows in view alone.

use std::sync::Arc;

use crate::app::state::session::RecordingId;

/// The shown rows' ids and columns, and the key `K` of everything they were computed from (the
/// browser's `ShownKey`).
pub(super) struct ShownRows<K, C> {
    key: Option<K>,
    ids: Arc<[RecordingId]>,
    columns: Vec<C>,
}

impl<K, C> Default for ShownRows<K, C> {
    fn default() -> Self {
        Self {
            key: None,
            ids: Arc::from([]),
            columns: Vec::new(),
        }
    }
}

impl<K: PartialEq, C> ShownRows<K, C> {
    /// Keeps the rows, or computes them again with `compute` when `key` differs from the last.
    pub fn refresh(&mut self, key: K, compute: impl FnOnce() -> (Vec<RecordingId>, Vec<C>)) {
        if self.key.as_ref() != Some(&key) {
            let (ids, columns) = compute();
            (self.ids, self.columns) = (ids.into(), columns);
            self.key = Some(key);
        }
    }

    /// The ids of the rows shown, in order (as of the last refresh).
    pub fn ids(&self) -> &[RecordingId] {
        &self.ids
    }

    /// The columns shown (as of the last refresh).
    pub fn columns(&self) -> &[C] {
        &self.columns
    }
}
