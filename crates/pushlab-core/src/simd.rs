//! Run-time choice of the widest SIMD the CPU has, for the model's hot loops.
//!
//! The network's layers are 16 wide: with AVX2 a layer column is two 8-lane registers instead of four
//! 4-lane ones, which roughly halves the instructions of a prediction or an online step. The same
//! generic code is compiled twice — once for the baseline x86-64 (SSE2) and once inside a
//! `#[target_feature(enable = "avx2")]` function — and the AVX2 copy is called only after checking the
//! CPU at run time, so one binary runs everywhere. Lane-wise results are identical in both copies (the
//! same operations in the same order; no fused multiply-add), so the choice never changes a number.

/// Whether the AVX2 copies of the hot loops may run on this CPU (checked once, then cached by std).
#[inline]
pub(crate) fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Defines `$name`, which runs `$portable` (an `#[inline(always)]` method of the same signature) in a
/// copy compiled for AVX2 when the CPU has it, and as is otherwise.
macro_rules! dispatch_simd {
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident $(<$($gen:ident : $bound:path),*>)? (&$self_:ident $(, $arg:ident : $ty:ty)* $(,)?) -> $ret:ty
        => $portable:ident, $avx2:ident
    ) => {
        $(#[$meta])*
        $vis fn $name $(<$($gen: $bound),*>)? (&$self_ $(, $arg: $ty)*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            if $crate::simd::avx2_available() {
                #[allow(unsafe_code)]
                // SAFETY: `$avx2` only requires AVX2, and the CPU was just checked to have it.
                return unsafe { $self_.$avx2($($arg),*) };
            }
            $self_.$portable($($arg),*)
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        fn $avx2 $(<$($gen: $bound),*>)? (&$self_ $(, $arg: $ty)*) -> $ret {
            $self_.$portable($($arg),*)
        }
    };
}
pub(crate) use dispatch_simd;
