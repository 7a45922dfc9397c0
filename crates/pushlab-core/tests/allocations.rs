//! The test binary's allocator: the system's, noting for each thread how many allocations it
//! made and the largest it asked for, so that a test can say a piece of work allocates nothing
//! (`control_allocations`) or never asks for more than a bound (`datasets_fuzz_seeds`). Per
//! thread, so that tests running beside one another do not add to each other's counts.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

pub struct Noting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

/// Allocations (and reallocations) made on this thread so far.
pub fn on_this_thread() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

/// The largest allocation this thread asked for since [`forget_largest`].
pub fn largest_on_this_thread() -> usize {
    LARGEST.with(Cell::get)
}

pub fn forget_largest() {
    LARGEST.with(|largest| largest.set(0));
}

fn note(size: usize) {
    // `try_with`: a thread being torn down has no counters left, and is not being measured.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
    let _ = LARGEST.try_with(|largest| largest.set(largest.get().max(size)));
}

// SAFETY: every call is passed on to the system allocator unchanged; only thread-local counters
// (const-initialised, so they never allocate) are written.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Noting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        // SAFETY: the caller's contract, passed on.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract, passed on.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        // SAFETY: the caller's contract, passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}
