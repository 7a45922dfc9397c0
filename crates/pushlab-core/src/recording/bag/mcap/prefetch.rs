//! Compressed chunks read and decompressed ahead, on worker threads, while the reading thread
//! visits the chunk before: decompressing is most of the time a zstd camera bag takes (its JPEG
//! bytes are entropy-coded too, so every chunk holding a pose must be decompressed whole), and a
//! second core halves it. At most [`AHEAD`] chunks wait decompressed, so memory stays bounded by
//! a few chunks whatever the file's size.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, sync_channel};
use std::thread::Scope;

use super::chunk::read_whole;
use super::records::{ChunkHeader, ChunkIndex};
use super::source::Source;
use crate::recording::bag::problem::BagProblem;

/// Decompressed chunks that may wait to be visited.
const AHEAD: usize = 4;

/// A chunk read whole: its header and records, or why not.
type Read = Result<(ChunkHeader, Vec<u8>), BagProblem>;

/// The chunks being decompressed ahead.
pub(super) struct Prefetch {
    results: Option<Receiver<(usize, Read)>>,
    /// Chunks decompressed before the one being waited for.
    arrived: BTreeMap<usize, Read>,
    /// The chunks asked for, in order: those not taken when a later one is are dropped.
    planned: Vec<usize>,
}

impl Prefetch {
    /// Starts workers (one per core, at most two) decompressing `chunks[i]` for each `i` of
    /// `planned`, in order. None start for fewer than two chunks: there is nothing to overlap.
    /// `next` counts the chunks the workers took; it outlives them.
    #[cfg_attr(
        target_arch = "wasm32",
        expect(clippy::disallowed_methods, reason = "a page returns before any spawn")
    )]
    pub(super) fn start<'scope, 'env, S: Source + ?Sized>(
        scope: &'scope Scope<'scope, 'env>,
        source: &'env S,
        chunks: &'env [ChunkIndex],
        planned: &'env [usize],
        next: &'env AtomicUsize,
    ) -> Self {
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get().min(2));
        // A page has one thread (spawning panics there): its chunks are decompressed as read.
        if planned.len() < 2 || cfg!(target_arch = "wasm32") {
            return Self {
                results: None,
                arrived: BTreeMap::new(),
                planned: Vec::new(),
            };
        }
        let (send, results) = sync_channel(AHEAD);
        for _ in 0..workers {
            let send = send.clone();
            scope.spawn(move || {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&index) = planned.get(k) else { break };
                    // The reader stopped (an error, cancelled): nothing more is wanted.
                    if send
                        .send((index, read_whole(source, &chunks[index])))
                        .is_err()
                    {
                        break;
                    }
                }
            });
        }
        Self {
            results: Some(results),
            arrived: BTreeMap::new(),
            planned: planned.to_vec(),
        }
    }

    /// Chunk `index` read whole, when it was planned; `None` when it was not (the caller reads
    /// it itself).
    pub(super) fn take(&mut self, index: usize) -> Option<Read> {
        if self.planned.binary_search(&index).is_err() {
            return None;
        }
        // Chunks planned before this one and not taken are no longer wanted.
        self.arrived.retain(|&k, _| k >= index);
        if let Some(read) = self.arrived.remove(&index) {
            return Some(read);
        }
        let results = self.results.as_ref()?;
        while let Ok((k, read)) = results.recv() {
            if k == index {
                return Some(read);
            }
            if k > index {
                self.arrived.insert(k, read);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use std::sync::mpsc::sync_channel;

    use super::*;

    /// A stand-in for chunk `k` read: an error naming it, which is all the bookkeeping looks at.
    fn read(k: usize) -> Read {
        Err(BagProblem::Mcap(format!("chunk {k}")))
    }

    fn name(read: Option<Read>) -> String {
        match read {
            Some(Err(BagProblem::Mcap(name))) => name,
            other => panic!("expected a chunk, got {other:?}"),
        }
    }

    #[test]
    fn chunks_arriving_out_of_order_are_each_taken_once_in_order() {
        let (send, results) = sync_channel(8);
        // Two workers finish 3 and 5 before 1, as a second core does.
        for k in [3, 1, 5, 4] {
            send.send((k, read(k))).unwrap();
        }
        drop(send);
        let mut prefetch = Prefetch {
            results: Some(results),
            arrived: BTreeMap::new(),
            planned: vec![1, 3, 4, 5],
        };
        assert!(
            prefetch.take(2).is_none(),
            "chunk 2 was not planned: read by the caller"
        );
        assert_eq!(
            name(prefetch.take(3)),
            "chunk 3",
            "1 was skipped, 3 arrived first"
        );
        // 4 and 5 arrived while 3 was waited for, or are still in the channel: none is lost.
        assert_eq!(name(prefetch.take(4)), "chunk 4");
        assert_eq!(name(prefetch.take(5)), "chunk 5");
        assert!(prefetch.arrived.is_empty(), "nothing kept once taken");
    }
}
