//! Frames read and decoded on a worker thread into a cache bounded in bytes, so that whoever shows
//! them (the app's camera panel, a bench) never waits on a disk or a JPEG decoder, and memory stays
//! bounded by the frames shown rather than by the size of the recording.
//!
//! The caller says, once per drawn frame, which frames it wants, most wanted first: the frames
//! shown, then those it will show next (prefetch while playing). Each [`FrameDecoder::want`]
//! replaces the previous list, so a scrub that races over a thousand frames decodes the one it
//! stops on, not the thousand behind it. The worker decodes what is wanted and not yet cached, in
//! order; when the cache is over its budget it forgets the frames used longest ago, never one that
//! is wanted now. A frame that cannot be read or decoded is cached as its error, so a corrupt frame
//! is reported once and the rest play on.
//!
//! Where no thread can be started (a browser tab: `std::thread` has none there), the decoder
//! decodes on the caller instead, one frame per [`FrameDecoder::want`] — the first wanted frame
//! not cached, so the frame shown comes first and the prefetch follows a frame a draw — so that a
//! page's camera panel shows its pictures rather than waiting for a worker that never starts.

use std::collections::HashMap;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Duration;

use web_time::Instant;

use super::{CameraStream, FrameProblem, FrameReader, RgbaImage, decode};

/// A frame decoded, or why it could not be.
pub type Decoded = Result<Arc<RgbaImage>, FrameProblem>;

/// The default budget: about 70 frames of 1280×720 RGBA.
pub const DEFAULT_BUDGET_BYTES: usize = 256 << 20;

/// One frame of one stream. Streams are told apart by their allocation, which the wanted list keeps
/// alive while a key is in use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct FrameKey {
    stream: usize,
    frame: usize,
}

impl FrameKey {
    fn of(stream: &Arc<CameraStream>, frame: usize) -> Self {
        Self {
            stream: Arc::as_ptr(stream) as usize,
            frame,
        }
    }
}

struct Entry {
    /// Kept so that the stream's address, which the key holds, is not reused while cached.
    _stream: Arc<CameraStream>,
    decoded: Decoded,
    bytes: usize,
    last_used: u64,
}

/// What the caller and the worker share, behind one lock.
#[derive(Default)]
struct Shared {
    wanted: Vec<(Arc<CameraStream>, usize)>,
    cache: HashMap<FrameKey, Entry>,
    cached_bytes: usize,
    /// A use counter: the entry with the smallest `last_used` is forgotten first.
    tick: u64,
    /// The frame the worker is decoding, so that the caller knows it is on its way.
    decoding: Option<FrameKey>,
    quit: bool,
}

/// Reads and decodes frames on its own thread, or on the caller where there are no threads (see
/// the module doc).
pub struct FrameDecoder {
    shared: Arc<(Mutex<Shared>, Condvar)>,
    budget_bytes: usize,
    worker: Option<JoinHandle<()>>,
    /// The readers of a decoder without a worker, which decodes on the caller.
    readers_here: Mutex<Readers>,
}

/// Each wanted stream's reader, by the stream's address.
type Readers = HashMap<usize, Box<dyn FrameReader>>;

impl Default for FrameDecoder {
    fn default() -> Self {
        Self::new(DEFAULT_BUDGET_BYTES)
    }
}

impl std::fmt::Debug for FrameDecoder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FrameDecoder")
            .field("budget_bytes", &self.budget_bytes)
            .field("cached_bytes", &self.cached_bytes())
            .finish()
    }
}

impl FrameDecoder {
    /// A decoder whose cache holds at most `budget_bytes` of decoded pixels (and always the frames
    /// wanted now, even when one alone is larger).
    /// Where no thread can be started (a page), it decodes on the caller: see
    /// [`Self::on_caller`].
    pub fn new(budget_bytes: usize) -> Self {
        let mut decoder = Self::on_caller(budget_bytes);
        let shared = Arc::clone(&decoder.shared);
        decoder.worker = std::thread::Builder::new()
            .name("pushlab-frames".to_owned())
            .spawn(move || work(&shared, budget_bytes))
            .ok();
        decoder
    }

    /// A decoder without a worker: each [`Self::want`] decodes the first wanted frame not cached,
    /// on the caller (what a browser tab gets from [`Self::new`]).
    pub fn on_caller(budget_bytes: usize) -> Self {
        Self {
            shared: Arc::new((Mutex::new(Shared::default()), Condvar::new())),
            budget_bytes,
            worker: None,
            readers_here: Mutex::new(HashMap::new()),
        }
    }

    /// The frames wanted now, most wanted first; replaces the previous list.
    pub fn want(&self, frames: Vec<(Arc<CameraStream>, usize)>) {
        let (lock, wake) = &*self.shared;
        let mut shared = lock_of(lock);
        if shared.wanted.len() == frames.len()
            && (shared.wanted.iter().zip(&frames))
                .all(|((a, i), (b, j))| Arc::ptr_eq(a, b) && i == j)
        {
            drop(shared);
            self.decode_here();
            return;
        }
        shared.wanted = frames;
        wake.notify_all();
        drop(shared);
        self.decode_here();
    }

    /// Without a worker: decodes the first wanted frame not cached, on the caller.
    fn decode_here(&self) {
        if self.worker.is_some() {
            return;
        }
        let mut readers = self
            .readers_here
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let next = {
            let state = lock_of(&self.shared.0);
            // Readers of streams no longer wanted hold open files and decompressed chunks.
            readers.retain(|key, _| {
                (state.wanted.iter()).any(|(s, _)| Arc::as_ptr(s) as usize == *key)
            });
            next_wanted(&state)
        };
        if let Some(next) = next {
            decode_one(&self.shared.0, &mut readers, next, self.budget_bytes);
        }
    }

    /// Frame `frame` of `stream` when it is decoded (or failed); `None` while it is not.
    pub fn get(&self, stream: &Arc<CameraStream>, frame: usize) -> Option<Decoded> {
        let mut shared = lock_of(&self.shared.0);
        shared.tick += 1;
        let tick = shared.tick;
        let entry = shared.cache.get_mut(&FrameKey::of(stream, frame))?;
        entry.last_used = tick;
        Some(entry.decoded.clone())
    }

    /// Waits up to `timeout` for frame `frame` of `stream`, asking for it alone when it is not
    /// wanted already: what a seek does when it must show the frame before going on.
    pub fn wait_for(
        &self,
        stream: &Arc<CameraStream>,
        frame: usize,
        timeout: Duration,
    ) -> Option<Decoded> {
        let key = FrameKey::of(stream, frame);
        if self.worker.is_none() {
            // No worker to wait for (and a page cannot wait): decode it now.
            self.want(vec![(Arc::clone(stream), frame)]);
            return self.get(stream, frame);
        }
        let deadline = Instant::now() + timeout;
        let (lock, wake) = &*self.shared;
        let mut shared = lock_of(lock);
        if !(shared.wanted.iter()).any(|(s, i)| FrameKey::of(s, *i) == key) {
            shared.wanted = vec![(Arc::clone(stream), frame)];
            wake.notify_all();
        }
        loop {
            if let Some(entry) = shared.cache.get(&key) {
                return Some(entry.decoded.clone());
            }
            let left = deadline.checked_duration_since(Instant::now())?;
            shared = wake
                .wait_timeout(shared, left)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }

    /// Whether a wanted frame is still being read or decoded (the caller keeps redrawing until
    /// it is not).
    pub fn is_busy(&self) -> bool {
        let shared = lock_of(&self.shared.0);
        shared.decoding.is_some()
            || (shared.wanted.iter()).any(|(s, i)| !shared.cache.contains_key(&FrameKey::of(s, *i)))
    }

    /// Bytes of decoded pixels cached.
    pub fn cached_bytes(&self) -> usize {
        lock_of(&self.shared.0).cached_bytes
    }

    /// The cache's budget in bytes.
    pub fn budget_bytes(&self) -> usize {
        self.budget_bytes
    }

    /// Forgets every cached frame and every wish (another recording is shown).
    pub fn clear(&self) {
        let mut shared = lock_of(&self.shared.0);
        shared.wanted.clear();
        shared.cache.clear();
        shared.cached_bytes = 0;
    }
}

impl Drop for FrameDecoder {
    fn drop(&mut self) {
        {
            let (lock, wake) = &*self.shared;
            lock_of(lock).quit = true;
            wake.notify_all();
        }
        if let Some(worker) = self.worker.take() {
            // A worker that panicked has nothing left to say.
            let _ = worker.join();
        }
    }
}

/// The lock, even after a panic elsewhere: the cache holds no invariant a panic could break halfway.
fn lock_of(lock: &Mutex<Shared>) -> MutexGuard<'_, Shared> {
    lock.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The worker: decode the first wanted frame not cached, until told to quit.
fn work(shared: &(Mutex<Shared>, Condvar), budget_bytes: usize) {
    let (lock, wake) = shared;
    let mut readers = Readers::new();
    loop {
        let next = {
            let mut state = lock_of(lock);
            loop {
                if state.quit {
                    return;
                }
                if let Some(next) = next_wanted(&state) {
                    break next;
                }
                // Readers of streams no longer wanted hold open files and decompressed chunks.
                readers.retain(|key, _| {
                    (state.wanted.iter()).any(|(s, _)| Arc::as_ptr(s) as usize == *key)
                });
                state = wake.wait(state).unwrap_or_else(PoisonError::into_inner);
            }
        };
        decode_one(lock, &mut readers, next, budget_bytes);
        wake.notify_all();
    }
}

/// The first wanted frame not cached.
fn next_wanted(state: &Shared) -> Option<(Arc<CameraStream>, usize)> {
    (state.wanted.iter())
        .find(|(s, i)| !state.cache.contains_key(&FrameKey::of(s, *i)))
        .map(|(s, i)| (Arc::clone(s), *i))
}

/// Reads and decodes one frame, the lock not held meanwhile, and caches it if it is still wanted.
fn decode_one(
    lock: &Mutex<Shared>,
    readers: &mut Readers,
    (stream, frame): (Arc<CameraStream>, usize),
    budget_bytes: usize,
) {
    let key = FrameKey::of(&stream, frame);
    lock_of(lock).decoding = Some(key);
    let reader = readers.entry(key.stream).or_insert_with(|| stream.reader());
    let decoded = reader
        .read(frame)
        .and_then(|encoded| Ok(Arc::new(decode(&encoded)?)));
    let mut state = lock_of(lock);
    state.decoding = None;
    // A clear() while decoding: the stream may be gone, and the frame is not wanted.
    if (state.wanted.iter()).any(|(s, i)| FrameKey::of(s, *i) == key) {
        insert(&mut state, (stream, frame), decoded, budget_bytes);
    }
}

/// Caches `decoded`, then forgets the frames used longest ago that are not wanted until the cache
/// fits its budget.
fn insert(
    state: &mut Shared,
    (stream, frame): (Arc<CameraStream>, usize),
    decoded: Decoded,
    budget_bytes: usize,
) {
    let key = FrameKey::of(&stream, frame);
    let bytes = match &decoded {
        Ok(image) => image.pixels.len(),
        Err(problem) => problem.to_string().len(),
    };
    state.tick += 1;
    let last_used = state.tick;
    state.cached_bytes += bytes;
    state.cache.insert(
        key,
        Entry {
            _stream: stream,
            decoded,
            bytes,
            last_used,
        },
    );
    while state.cached_bytes > budget_bytes {
        let oldest = (state.cache.iter())
            .filter(|(k, _)| !(state.wanted.iter()).any(|(s, i)| FrameKey::of(s, *i) == **k))
            .min_by_key(|(_, e)| e.last_used)
            .map(|(k, _)| *k);
        let Some(oldest) = oldest else { break };
        if let Some(entry) = state.cache.remove(&oldest) {
            state.cached_bytes -= entry.bytes;
        }
    }
}

#[cfg(test)]
mod tests;
