//! The dense-layer kernels of the MLP on fixed-size arrays: multiply-adds 16 lanes wide that the
//! compiler vectorises, generic over the float type and over fused (FMA) or portable multiply-adds.

use super::shape::HIDDEN;
use crate::real::Real;
use crate::simd::MulAdd;

/// `dw[j] += Σ_s x[s][j] dz[s]`, `db += Σ_s dz[s]`, summed in sample order: a dense layer's weight
/// gradient over a batch. Two columns at a time, each kept in registers across the samples (rather
/// than read and written back once per sample).
#[inline(always)]
pub(super) fn accumulate_outer_batch<T: Real, A: MulAdd, const I: usize, const O: usize>(
    dw: &mut [[T; O]; I],
    db: &mut [T; O],
    x: &[[T; I]],
    dz: &[[T; O]],
) {
    for (j, pair) in dw.chunks_mut(2).enumerate() {
        let (first, second) = pair.split_at_mut(1);
        let mut a = first[0];
        match second.first_mut() {
            Some(b_column) => {
                let mut b = *b_column;
                for (xs, ds) in x.iter().zip(dz) {
                    axpy::<T, A, O>(&mut a, ds, xs[2 * j]);
                    axpy::<T, A, O>(&mut b, ds, xs[2 * j + 1]);
                }
                *b_column = b;
            }
            None => {
                for (xs, ds) in x.iter().zip(dz) {
                    axpy::<T, A, O>(&mut a, ds, xs[2 * j]);
                }
            }
        }
        first[0] = a;
    }
    let mut b = *db;
    for ds in dz {
        for (g, &d) in b.iter_mut().zip(ds) {
            *g = *g + d;
        }
    }
    *db = b;
}

/// `z += a · x`, lane by lane.
#[inline(always)]
pub(super) fn axpy<T: Real, A: MulAdd, const N: usize>(z: &mut [T; N], a: &[T; N], x: T) {
    for (zi, &ai) in z.iter_mut().zip(a) {
        *zi = A::mul_add(ai, x, *zi);
    }
}

/// `z = b + Σ_j w[j] x[j]`: one dense layer, as 16-wide multiply-adds.
#[inline(always)]
pub(super) fn dense<T: Real, A: MulAdd, const I: usize, const O: usize>(
    w: &[[T; O]; I],
    b: &[T; O],
    x: &[T; I],
) -> [T; O] {
    let mut z = sum_of_columns::<T, A, I, O>(w, x);
    for (zi, &bi) in z.iter_mut().zip(b) {
        *zi = *zi + bi;
    }
    z
}

/// `Σ_j x[j] · columns[j]` in two interleaved partial sums (even and odd `j`), added at the end.
///
/// One running sum would chain all sixteen multiply-adds of a layer, each waiting for the previous
/// (4 cycles apiece), and a forward and backward pass would be mostly waiting. Two independent chains
/// halve that; more chains ran out of registers (measured slower).
#[inline(always)]
pub(super) fn sum_of_columns<T: Real, A: MulAdd, const I: usize, const O: usize>(
    columns: &[[T; O]; I],
    x: &[T; I],
) -> [T; O] {
    // Each sum starts with a product rather than a multiply-add onto zero (the same value, one
    // instruction and one register fewer).
    let mut even = [T::zero(); O];
    let mut odd = [T::zero(); O];
    if I > 0 {
        for (e, &c) in even.iter_mut().zip(&columns[0]) {
            *e = c * x[0];
        }
    }
    if I > 1 {
        for (o, &c) in odd.iter_mut().zip(&columns[1]) {
            *o = c * x[1];
        }
    }
    let mut j = 2;
    while j + 1 < I {
        axpy::<T, A, O>(&mut even, &columns[j], x[j]);
        axpy::<T, A, O>(&mut odd, &columns[j + 1], x[j + 1]);
        j += 2;
    }
    if j < I {
        axpy::<T, A, O>(&mut even, &columns[j], x[j]);
    }
    for (e, o) in even.iter_mut().zip(odd) {
        *e = *e + o;
    }
    even
}

/// `Σ_i a[i] b[i]` of two 16-wide vectors, summed as a tree (8 + 8, 4 + 4, 2 + 2, 1 + 1) so that it
/// vectorises; a left-to-right sum would be sixteen dependent additions.
#[inline(always)]
pub(super) fn dot<T: Real, A: MulAdd>(a: &[T; HIDDEN], b: &[T; HIDDEN]) -> T {
    // Plain loops rather than `array::from_fn` closures, which might not be inlined into the caller's
    // AVX2 + FMA copy.
    let mut p = [T::zero(); 8];
    for i in 0..8 {
        p[i] = A::mul_add(a[i + 8], b[i + 8], a[i] * b[i]);
    }
    let mut q = [T::zero(); 4];
    for i in 0..4 {
        q[i] = p[i] + p[i + 4];
    }
    (q[0] + q[2]) + (q[1] + q[3])
}

/// ReLU, branch-free.
#[inline(always)]
pub(super) fn relu<T: Real, const N: usize>(mut z: [T; N]) -> [T; N] {
    for zi in &mut z {
        *zi = if *zi > T::zero() { *zi } else { T::zero() };
    }
    z
}

/// Gradient through ReLU given its output `a`: passes where the unit was active.
#[inline(always)]
pub(super) fn relu_backward<T: Real, const N: usize>(a: &[T; N], d: &[T; N]) -> [T; N] {
    let mut out = *d;
    for (o, &ai) in out.iter_mut().zip(a) {
        // A select, not a conditional store, so that it vectorises.
        *o = if ai > T::zero() { *o } else { T::zero() };
    }
    out
}

/// `dx = Σ_i dz[i] · wt[i]`: the gradient with respect to a dense layer's input, from the transposed
/// weights (`wt[i][j] = w[j][i]`), as broadcast multiply-adds.
#[inline(always)]
pub(super) fn back_through<T: Real, A: MulAdd, const I: usize, const O: usize>(
    wt: &[[T; I]; O],
    dz: &[T; O],
) -> [T; I] {
    sum_of_columns::<T, A, O, I>(wt, dz)
}

/// `dw[j][i] += x[j] dz[i]`, `db += dz`: a dense layer's weight gradient.
#[inline(always)]
pub(super) fn accumulate_outer<T: Real, A: MulAdd, const I: usize, const O: usize>(
    dw: &mut [[T; O]; I],
    db: &mut [T; O],
    x: &[T; I],
    dz: &[T; O],
) {
    for (column, &xj) in dw.iter_mut().zip(x) {
        axpy::<T, A, O>(column, dz, xj);
    }
    for (g, &dzi) in db.iter_mut().zip(dz) {
        *g = *g + dzi;
    }
}
