//! The one CPU-feature seam: whether the vector loops may run, and the helpers they share.
//!
//! Every vectorised loop (the vertex transform, the span fast paths' chunks, the narrow small-triangle
//! fill) is entered through [`avx2`]: it gives an [`Avx2`] token only when the CPU has AVX2 (detected at run
//! time, the answer cached) and no test on this thread asked for the portable loops. A loop's safe entry
//! takes the token, which proves the feature is there, and calls its `#[target_feature]` body: that call is
//! the one `unsafe` in each AVX2 file. Each vector loop repeats its portable reference operation for
//! operation, and a unit test beside it holds the two bit for bit (the tests switch the vector loops off with
//! `force_portable` to compare).

#[cfg(target_arch = "x86_64")]
pub(crate) mod x86;

/// Asks the CPU to bring the cache line holding `value` into the nearest cache, without waiting for it: for
/// records a loop will read a few iterations later, at places the hardware prefetcher cannot guess. A plain
/// read would do the same but hold up every instruction after it until the line arrives; a prefetch does
/// not. A no-op where the CPU has no such instruction.
#[inline(always)]
pub(crate) fn prefetch<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch reads nothing the program sees and never faults; the address comes from a live
        // reference. SSE, which the instruction needs, is part of every x86_64 CPU.
        #[allow(unsafe_code)]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(std::ptr::from_ref(value).cast::<i8>());
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// Proof that the AVX2 loops may run on this CPU: made only by [`avx2`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx2(());

/// An [`Avx2`] token when the CPU has AVX2 and this thread has not been asked for the portable loops.
#[inline(always)]
pub(crate) fn avx2() -> Option<Avx2> {
    (has_avx2() && !portable_forced()).then_some(Avx2(()))
}

/// Whether the CPU has AVX2 (detected once; the detection caches its answer).
#[inline]
pub(crate) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
thread_local! {
    /// Set by tests to force the portable loops on CPUs with AVX2, to compare the two.
    static PORTABLE_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Makes this thread use (`true`) or stop using the portable loops only.
#[cfg(test)]
pub(crate) fn force_portable(on: bool) {
    PORTABLE_ONLY.with(|p| p.set(on));
}

/// True when a test asked for the portable loops only.
#[inline(always)]
fn portable_forced() -> bool {
    #[cfg(test)]
    {
        PORTABLE_ONLY.with(std::cell::Cell::get)
    }
    #[cfg(not(test))]
    {
        false
    }
}
