//! Fixed-point screen coordinates and the exact integer arithmetic the fill rule relies on.
//!
//! Screen positions are snapped to [`Fx28_4`]: 28 integer bits and 4 fractional bits, so a vertex lands on a
//! grid of 1/16 pixel. Every coverage decision (which rows and which pixels a polygon covers) is made with
//! integers on that grid, so two polygons that share an edge make the same decision for every pixel centre
//! on it, whatever order they are drawn in and whichever thread draws them.

/// A screen coordinate in signed 28.4 fixed point (1/16 pixel steps), stored in an `i32`.
///
/// The renderer's guard band keeps every snapped coordinate well inside `±2^27` pixels, so products of two
/// coordinate differences fit in an `i64` with room to spare.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Fx28_4(pub i32);

impl Fx28_4 {
    /// Number of fractional bits.
    pub const FRAC_BITS: u32 = 4;
    /// One pixel in raw units.
    pub const ONE: i32 = 1 << Self::FRAC_BITS;
    /// Half a pixel in raw units (the offset of a pixel centre).
    pub const HALF: i32 = Self::ONE / 2;
    /// Largest magnitude, in pixels, that [`Fx28_4::from_f32`] accepts.
    pub const MAX_PIXELS: f32 = (1u32 << 26) as f32;

    /// Snaps a pixel coordinate to the nearest 1/16 pixel; `None` for NaN, infinities and out-of-range values.
    #[must_use]
    pub fn from_f32(v: f32) -> Option<Self> {
        if v.is_finite() && v.abs() <= Self::MAX_PIXELS {
            // Round half away from zero (as `f32::round`, without its libm call: the x86-64 baseline has no
            // rounding instruction). `s` is below 2^30, so truncation fits; the remainder is exact.
            let s = v * Self::ONE as f32;
            let t = s as i32;
            let frac = s - t as f32;
            Some(Self(t + i32::from(frac >= 0.5) - i32::from(frac <= -0.5)))
        } else {
            None
        }
    }

    /// The coordinate in pixels.
    #[must_use]
    pub fn to_f32(self) -> f32 {
        self.0 as f32 / Self::ONE as f32
    }

    /// Index of the first pixel whose centre (`i + 0.5`) is at or after this coordinate.
    ///
    /// This is the whole fill rule in one function: a span `[left, right)` covers the pixels
    /// `first_centre_at_or_after(left) .. first_centre_at_or_after(right)`, so a centre exactly on a shared
    /// edge belongs to the polygon on its right (or below), never to both, never to neither.
    #[must_use]
    pub fn first_centre_at_or_after(self) -> i32 {
        // ceil((n - 8) / 16) = floor((n + 7) / 16): a shift, not a division (set-up does this per corner).
        ((i64::from(self.0) + i64::from(Self::ONE - 1 - Self::HALF)) >> 4) as i32
    }
}

/// `ceil(n / d)` for `d > 0`, exact for all `i64` inputs in range.
#[must_use]
pub fn ceil_div(n: i64, d: i64) -> i64 {
    debug_assert!(d > 0);
    let q = n.div_euclid(d);
    if n.rem_euclid(d) == 0 { q } else { q + 1 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapping_rounds_as_f32_round() {
        let mut vs = vec![0.03125f32, -0.03125, 0.09375, -0.09375, 1e-30, -0.0, 4_194_303.97, 67_108_864.0];
        let mut seed = 0x9e37_79b9u32;
        for _ in 0..200_000 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            vs.push((seed as i32) as f32 / 31.0);
            vs.push(f32::from_bits(seed) % Fx28_4::MAX_PIXELS);
        }
        for v in vs {
            if let Some(f) = Fx28_4::from_f32(v) {
                assert_eq!(f.0, (v * 16.0).round() as i32, "{v}");
            }
        }
    }

    #[test]
    fn snapping_and_centres() {
        assert_eq!(Fx28_4::from_f32(1.5), Some(Fx28_4(24)));
        assert_eq!(Fx28_4::from_f32(-0.03), Some(Fx28_4(0)));
        assert_eq!(Fx28_4::from_f32(f32::NAN), None);
        assert_eq!(Fx28_4::from_f32(1e30), None);
        // The shift is the exact ceiling division, to the ends of the range.
        for n in (-4000..4000).chain([i32::MIN, i32::MIN + 7, i32::MAX - 7, i32::MAX]) {
            let exact = ceil_div(i64::from(n) - 8, 16);
            assert_eq!(i64::from(Fx28_4(n).first_centre_at_or_after()), exact, "raw {n}");
        }
        // A coordinate exactly on a centre includes that pixel; just after it, the next one.
        assert_eq!(Fx28_4(8).first_centre_at_or_after(), 0);
        assert_eq!(Fx28_4(9).first_centre_at_or_after(), 1);
        assert_eq!(Fx28_4(7).first_centre_at_or_after(), 0);
        assert_eq!(Fx28_4(-8).first_centre_at_or_after(), -1);
        assert_eq!(Fx28_4(-9).first_centre_at_or_after(), -1);
        assert_eq!(ceil_div(-7, 16), 0);
        assert_eq!(ceil_div(-16, 16), -1);
        assert_eq!(ceil_div(17, 16), 2);
    }
}
