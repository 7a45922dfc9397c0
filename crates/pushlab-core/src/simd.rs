//! Run-time choice of the widest SIMD the CPU has, for the model's hot loops.
//!
//! The network's layers are 16 wide: with AVX2 a layer column is two 8-lane registers instead of four
//! 4-lane ones, and with FMA a multiply-add is one instruction instead of two, which together more than
//! halve the instructions of a prediction, an online step or a training epoch. The same generic code is
//! compiled twice — once for the baseline x86-64 (SSE2, multiply then add) and once inside a
//! `#[target_feature(enable = "avx2,fma")]` function with fused multiply-adds — and the fast copy is
//! called only after checking the CPU at run time, so one binary runs everywhere.
//!
//! The two copies differ in rounding: a fused multiply-add rounds once where the plain copy rounds
//! twice. Results are therefore bit-identical run to run on one machine (same seed, same model), and on
//! every machine that has AVX2 and FMA (every x86-64 CPU since 2013–2015), but a CPU without them gets
//! results that differ in the last bits.

use crate::real::Real;

/// Whether the AVX2 + FMA copies of the hot loops may run on this CPU (checked once, then cached by
/// std).
#[inline]
#[cfg_attr(
    not(target_arch = "x86_64"),
    expect(dead_code, reason = "the dispatch calls it on x86-64 only")
)]
pub(crate) fn avx2_fma_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && !portable_asked()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether `PUSHLAB_SIMD=portable` asks for the portable copy on a CPU that has AVX2 and FMA: the
/// bits a CPU without them (and a browser tab, whose wasm has no FMA) compute, to compare with
/// (`scripts/web-test` runs `pushlab eval` so). Read once.
#[cfg(target_arch = "x86_64")]
fn portable_asked() -> bool {
    static PORTABLE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *PORTABLE.get_or_init(|| std::env::var("PUSHLAB_SIMD").is_ok_and(|v| v == "portable"))
}

/// How the hot loops compute `a · b + c`: chosen per compiled copy, because a fused multiply-add is a
/// single instruction where the CPU has FMA and a slow library call where it does not.
pub(crate) trait MulAdd: Copy {
    /// `a · b + c`.
    fn mul_add<T: Real>(a: T, b: T, c: T) -> T;
}

/// `a · b + c` rounded twice: the portable copy (and the f64 gradient checks).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Unfused;

impl MulAdd for Unfused {
    #[inline(always)]
    fn mul_add<T: Real>(a: T, b: T, c: T) -> T {
        a * b + c
    }
}

/// `a · b + c` rounded once, as one FMA instruction: only inside the `avx2,fma` copies.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(
    not(target_arch = "x86_64"),
    expect(dead_code, reason = "only the x86-64 AVX2 copies fuse")
)]
pub(crate) struct Fused;

impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add<T: Real>(a: T, b: T, c: T) -> T {
        a.mul_add(b, c)
    }
}

/// Defines `$name`, which runs `$portable::<A>` (an `#[inline(always)]` method of the same signature,
/// generic over `A: MulAdd`) in a copy compiled for AVX2 and FMA with `A = Fused` when the CPU has
/// them, and with `A = Unfused` otherwise.
///
/// With `=> unfused $portable, $avx2`, `$portable` is not generic and does its own arithmetic
/// (unfused): the AVX2 copy then only has wider registers and gives the portable copy's bits, since
/// the compiler never fuses a multiply and an add by itself. For passes whose results must keep the
/// bits of an unfused computation (offline training's validation loss and step-size calibration).
macro_rules! dispatch_simd {
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident (&$self_:ident $(, $arg:ident : $ty:ty)* $(,)?) -> $ret:ty
        => unfused $portable:ident, $avx2:ident
    ) => {
        $(#[$meta])*
        $vis fn $name (&$self_ $(, $arg: $ty)*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if $crate::simd::avx2_fma_available() {
                #[allow(unsafe_code)]
                // SAFETY: `$avx2` only requires AVX2 and FMA, and the CPU was just checked to have them.
                return unsafe { $self_.$avx2($($arg),*) };
            }
            $self_.$portable($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        fn $avx2 (&$self_ $(, $arg: $ty)*) -> $ret {
            $self_.$portable($($arg),*)
        }
    };
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident (&$self_:ident $(, $arg:ident : $ty:ty)* $(,)?) -> $ret:ty
        => $portable:ident, $avx2:ident
    ) => {
        $(#[$meta])*
        $vis fn $name (&$self_ $(, $arg: $ty)*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if $crate::simd::avx2_fma_available() {
                #[allow(unsafe_code)]
                // SAFETY: `$avx2` only requires AVX2 and FMA, and the CPU was just checked to have them.
                return unsafe { $self_.$avx2($($arg),*) };
            }
            $self_.$portable::<$crate::simd::Unfused>($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        fn $avx2 (&$self_ $(, $arg: $ty)*) -> $ret {
            $self_.$portable::<$crate::simd::Fused>($($arg),*)
        }
    };
}
pub(crate) use dispatch_simd;
