//! A small deterministic generator for the render module's randomised tests, so a failure reproduces from
//! its seed.

/// A 64-bit linear congruential generator (Knuth's MMIX constants), high bits out.
pub(crate) struct Lcg(pub(crate) u64);

impl Lcg {
    /// The next 31 random bits.
    pub(crate) fn next(&mut self) -> u32 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 33) as u32
    }

    /// A value in `0..n`.
    pub(crate) fn below(&mut self, n: u32) -> u32 {
        self.next() % n
    }

    /// A value in `lo..hi`.
    pub(crate) fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + self.below((hi - lo) as u32) as i32
    }

    /// A value in `0..1`.
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next() >> 7) as f32 / (1u32 << 24) as f32
    }
}
