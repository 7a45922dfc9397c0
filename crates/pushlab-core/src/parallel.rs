//! Work over many independent items spread over the machine's cores, in a way that keeps every bit
//! of a result whatever the number of cores.
//!
//! A sum over samples is the one place where running in parallel could change a result: added in
//! another order, floating-point terms round differently. So the items are cut into contiguous
//! slices; this thread works through the first, adding as it goes, while other threads compute the
//! later slices' per-item terms and hand them back to be added afterwards in order. The sum is then
//! the serial one, term for term.
//!
//! Only passes whose per-item work outweighs a thread's start pay for this: on this project's
//! 2-core virtual machine, a thread costs about 50 µs to start and join, and a pass that mostly
//! writes fresh memory (a sample's contact frame, its prepared form) gained nothing. And only where
//! a core is free: the slices are fixed halves, so with the other core busy the split costs a few
//! per cent (`train/train_epoch*`, `performance.md`).

use std::ops::Range;
use std::sync::OnceLock;

/// The fewest training samples a thread takes in offline training's per-sample passes (about
/// 0.4 ms of the curvature pass's work).
pub(crate) const SAMPLES_PER_WORKER: usize = 2048;

/// How many threads to use: the cores this process may run on, read once (reading them opens files
/// under `/sys` and `/proc` on Linux, a cost every training would pay again).
fn workers() -> usize {
    static WORKERS: OnceLock<usize> = OnceLock::new();
    *WORKERS.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Runs `first` on this thread over the first slice of `items` and `rest` on other threads over the
/// remaining slices, one thread each, every slice at least `min_slice` items (fewer items go to
/// `first` alone); returns `rest`'s results in the slices' order. Up to [`workers`] slices.
fn first_here_rest_elsewhere<T, R, F, G>(items: &[T], min_slice: usize, first: F, rest: G) -> Vec<R>
where
    T: Sync,
    R: Send,
    F: FnOnce(&[T]),
    G: Fn(&[T]) -> R + Sync,
{
    first_range_here_rest_elsewhere(
        items.len(),
        min_slice,
        |range| first(&items[range]),
        |range| rest(&items[range]),
    )
}

/// [`first_here_rest_elsewhere`] over the ranges of indices `0..len` rather than a slice's items.
#[cfg_attr(
    target_arch = "wasm32",
    expect(
        clippy::disallowed_methods,
        reason = "a page has no cores to count (available_parallelism fails): one slice, no spawn"
    )
)]
fn first_range_here_rest_elsewhere<R, F, G>(
    len: usize,
    min_slice: usize,
    first: F,
    rest: G,
) -> Vec<R>
where
    R: Send,
    F: FnOnce(Range<usize>),
    G: Fn(Range<usize>) -> R + Sync,
{
    let count = workers().min(len / min_slice.max(1)).max(1);
    if count == 1 {
        first(0..len);
        return Vec::new();
    }
    let slice = len.div_ceil(count);
    let rest = &rest;
    std::thread::scope(|scope| {
        let others: Vec<_> = (slice..len)
            .step_by(slice)
            .map(|start| scope.spawn(move || rest(start..(start + slice).min(len))))
            .collect();
        first(0..slice);
        others
            .into_iter()
            .map(|other| match other.join() {
                Ok(result) => result,
                // A thread panics only if `rest` does, which this thread would have too: pass it on.
                Err(panic) => std::panic::resume_unwind(panic),
            })
            .collect()
    })
}

/// `item(i)` for every `i` in `0..len`, in order, the later ranges computed on other cores: for
/// passes of independent items that only collect (each result is what a serial pass gives).
pub(crate) fn ordered_map<R: Send>(
    len: usize,
    min_slice: usize,
    item: impl Fn(usize) -> R + Sync,
) -> Vec<R> {
    let mut results = Vec::with_capacity(len);
    let later = first_range_here_rest_elsewhere(
        len,
        min_slice,
        |range| results.extend(range.map(&item)),
        |range| range.map(&item).collect::<Vec<R>>(),
    );
    for part in later {
        results.extend(part);
    }
    results
}

/// The sum over `items` of their terms, term for term the serial sum whatever the number of cores:
/// `terms` hands each item's terms of a slice, in the slice's order, to the function it is given;
/// `add` adds one to the total. This thread adds the first slice's as they come; the later slices'
/// are computed elsewhere, kept, and added after it in order.
pub(crate) fn ordered_sum<T, Term, Total>(
    items: &[T],
    min_slice: usize,
    mut total: Total,
    add: impl Fn(&mut Total, Term),
    terms: impl Fn(&[T], &mut dyn FnMut(Term)) + Sync,
) -> Total
where
    T: Sync,
    Term: Send,
{
    let later = first_here_rest_elsewhere(
        items,
        min_slice,
        |first| terms(first, &mut |term| add(&mut total, term)),
        |part| {
            let mut kept = Vec::with_capacity(part.len());
            terms(part, &mut |term| kept.push(term));
            kept
        },
    );
    for term in later.into_iter().flatten() {
        add(&mut total, term);
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_cover_the_items_once_in_order() {
        let items: Vec<u64> = (0..10_007).collect();
        for min_slice in [1, 100, 5_000, 20_000] {
            let mut seen = Vec::new();
            let rest = first_here_rest_elsewhere(
                &items,
                min_slice,
                |part| seen.extend_from_slice(part),
                <[u64]>::to_vec,
            );
            let first_len = seen.len();
            seen.extend(rest.into_iter().flatten());
            assert_eq!(seen, items, "min_slice {min_slice}");
            if min_slice > items.len() / 2 {
                assert_eq!(first_len, items.len(), "too few items to share");
            }
        }
        let none =
            first_here_rest_elsewhere(&[] as &[u64], 1, |part| assert!(part.is_empty()), |_| 0);
        assert!(none.is_empty());
    }

    #[test]
    fn an_ordered_map_is_the_serial_one() {
        for (len, min_slice) in [(0, 1), (7, 100), (10_007, 1_000), (10_007, 1)] {
            let serial: Vec<u64> = (0..len).map(|i| (i as u64).pow(2) % 97).collect();
            let mapped = ordered_map(len, min_slice, |i| (i as u64).pow(2) % 97);
            assert_eq!(mapped, serial, "{len} items, {min_slice} a slice");
        }
    }

    #[test]
    fn an_ordered_sum_has_the_bits_of_the_serial_one() {
        // Terms of very different sizes: any other order of addition rounds differently.
        let items: Vec<f64> = (0..9_001)
            .map(|i| 1.0 / f64::from(i + 1) * 1e3_f64.powi(i % 5))
            .collect();
        let serial = items.iter().fold(0.0, |total, x| total + x * x);
        let sum = ordered_sum(
            &items,
            1_000,
            0.0,
            |total: &mut f64, t| *total += t,
            |part, each| part.iter().for_each(|x| each(x * x)),
        );
        assert_eq!(sum.to_bits(), serial.to_bits());
        let halves = items[..4_500].iter().fold(0.0, |t, x| t + x * x)
            + items[4_500..].iter().fold(0.0, |t, x| t + x * x);
        assert_ne!(
            halves.to_bits(),
            serial.to_bits(),
            "the test's terms must be order-sensitive"
        );
    }
}
