//! Whether the AVX2 loops (the span chunks, the vertex transform and the narrow small triangles) may run:
//! detected at run time, and switched off by tests that compare them with their one-at-a-time references.

/// Whether the CPU has AVX2 (detected once; the detection caches its answer).
#[inline]
pub(super) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether the AVX2 loops should run: the CPU has AVX2 and no test on this thread asked for the portable
/// loops.
#[inline(always)]
pub(super) fn use_avx2() -> bool {
    has_avx2() && !portable_forced()
}

#[cfg(test)]
thread_local! {
    /// Set by tests to force the portable loops on CPUs with AVX2, to compare the two.
    static PORTABLE_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Makes this thread use (`true`) or stop using the portable loops only.
#[cfg(test)]
pub(super) fn force_portable(on: bool) {
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
