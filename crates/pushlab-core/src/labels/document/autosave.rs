//! When a document saves itself.

use super::super::file::LabelFileError;
use super::LabelDocument;

/// When to save without being asked: shortly after the last edit, but at least every `max_delay_s`
/// while edits keep coming (painting during playback), and after a failure only every `retry_s`.
/// Time is passed in, never read from the clock, so this is testable.
#[derive(Clone, Debug)]
pub struct Autosave {
    /// Quiet time after the last edit before saving, seconds.
    pub delay_s: f64,
    /// Longest time edits stay unsaved while editing continues, seconds.
    pub max_delay_s: f64,
    /// Wait after a failed save before trying again, seconds.
    pub retry_s: f64,
    /// (state id, time it was first seen) of the latest edit.
    last_edit: Option<(u64, f64)>,
    /// When unsaved edits were first seen.
    dirty_since: Option<f64>,
    last_failure: Option<f64>,
}

impl Default for Autosave {
    fn default() -> Self {
        Self {
            delay_s: 0.5,
            max_delay_s: 5.0,
            retry_s: 5.0,
            last_edit: None,
            dirty_since: None,
            last_failure: None,
        }
    }
}

impl Autosave {
    /// Call once per app update with the current time in seconds. Saves when due and returns the
    /// outcome; `None` when nothing was due.
    pub fn poll(
        &mut self,
        doc: &mut LabelDocument,
        now_s: f64,
    ) -> Option<Result<(), LabelFileError>> {
        if !doc.is_dirty() {
            self.last_edit = None;
            self.dirty_since = None;
            self.last_failure = None;
            return None;
        }
        let state = doc.state_id();
        let edited_at = match self.last_edit {
            Some((s, t)) if s == state => t,
            _ => {
                self.last_edit = Some((state, now_s));
                now_s
            }
        };
        let dirty_since = *self.dirty_since.get_or_insert(now_s);
        if self.last_failure.is_some_and(|t| now_s - t < self.retry_s) {
            return None;
        }
        let due = now_s - edited_at >= self.delay_s || now_s - dirty_since >= self.max_delay_s;
        if !due {
            return None;
        }
        let result = doc.save();
        match &result {
            Ok(()) => {
                self.dirty_since = None;
                self.last_failure = None;
            }
            Err(_) => self.last_failure = Some(now_s),
        }
        Some(result)
    }
}
