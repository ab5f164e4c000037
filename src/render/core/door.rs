//! The screen door: which pixels a see-through or fading polygon leaves alone, a fixed 4x4 pattern instead
//! of blending (as Sega's Model 1 drew translucency with a checkerboard).
//!
//! A pixel `(x, y)` has the rank `BAYER[y % 4][x % 4]`, 0 to 15 (the ordered-dither matrix: every run of
//! ranks is spread evenly over the 4x4 block). A door of coverage `k` quarters draws the pixels whose rank
//! is below `4k`, or, inverted, the others; so a door and its inverse draw every pixel exactly once, which
//! is what a level-of-detail cross-fade needs: the new model through `k` quarters, the old one through the
//! rest. Half coverage not inverted is the checkerboard of pixels with `x + y` even (the ghost car).

/// Set in a door drawn in a frame of four rows a pixel ([`Door::in_tall_frame`]).
const TALL: u8 = 8;

/// The ordered-dither ranks of a 4x4 block, by row.
const BAYER: [[u8; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// A screen door, or none: 3 bits (quarters drawn, 1 to 3, and whether inverted), so it fits the spare
/// bits of a polygon record.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Door(u8);

impl Door {
    /// No door: every pixel is drawn.
    pub const NONE: Door = Door(0);
    /// The checkerboard of see-through instances: pixels with `x + y` even.
    pub const CHECKERBOARD: Door = Door(2);

    /// The door drawing `quarters` (1 to 3) of the pixels, or the other `4 - quarters` when `inverted`;
    /// `None` for 0 or 4 quarters (nothing, or every pixel, is no door).
    #[must_use]
    pub fn quarters(quarters: u8, inverted: bool) -> Option<Door> {
        (1..=3).contains(&quarters).then_some(Door(quarters | u8::from(inverted) << 2))
    }

    /// The 3-bit code (0 for none), for packing.
    #[must_use]
    pub(crate) fn bits(self) -> u8 {
        self.0 & 7
    }

    /// The door of a 3-bit code from [`Door::bits`] (a code with no quarters is none).
    #[must_use]
    pub(crate) fn from_bits(bits: u8) -> Door {
        if bits & 3 == 0 { Door::NONE } else { Door(bits & 7) }
    }

    /// Whether it is no door.
    #[must_use]
    #[inline(always)]
    pub fn is_none(self) -> bool {
        self.0 & 3 == 0
    }

    /// The same door for a frame drawn four rows a pixel ([`crate::render::Antialias::RotatedGrid`]), when
    /// `tall`: pixel `(x, 4y + k)` of that frame takes the rank of pixel `(2x + k % 2, 2y + k / 2)` of a frame
    /// of twice the width and height, so a pixel's four rows see its 2x2 block of ranks, as 2x2 supersampling
    /// does, and a fade blends in steps of a quarter instead of dithering. No door stays none.
    #[must_use]
    pub(crate) fn in_tall_frame(self, tall: bool) -> Door {
        if tall && self.0 & 3 != 0 { Door((self.0 & 7) | TALL) } else { self }
    }

    /// Whether the pixel at `(x, y)` is left alone (always false without a door).
    #[must_use]
    #[inline(always)]
    pub fn hides(self, x: i32, y: i32) -> bool {
        if self.0 & 3 == 0 {
            return false;
        }
        let (x, y) = if self.0 & TALL != 0 { (2 * x + (y & 1), 2 * (y >> 2) + (y >> 1 & 1)) } else { (x, y) };
        let rank = BAYER[(y & 3) as usize][(x & 3) as usize];
        let inside = rank < 4 * (self.0 & 3);
        inside == (self.0 & 4 != 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_door_in_a_tall_frame_takes_the_ranks_of_the_doubled_frame() {
        for q in 1..=3 {
            for inverted in [false, true] {
                let door = Door::quarters(q, inverted).unwrap();
                let tall = door.in_tall_frame(true);
                for y in -6..6 {
                    for x in -6..6 {
                        // Rows 4y..4y + 4 of the tall frame stand for the cells (0, 0), (1, 0), (0, 1), (1, 1).
                        let drawn: Vec<bool> = (0..4).map(|k| !tall.hides(x, 4 * y + k)).collect();
                        let want: Vec<bool> = (0..4).map(|k| !door.hides(2 * x + k % 2, 2 * y + k / 2)).collect();
                        assert_eq!(drawn, want, "({x}, {y}) at {q} quarters, inverted {inverted}");
                        // Every 2x2 block of ranks holds one of each quarter: the four rows draw q of 4.
                        let n = drawn.iter().filter(|&&d| d).count();
                        assert_eq!(n, if inverted { 4 - usize::from(q) } else { usize::from(q) });
                    }
                }
                assert_eq!(door.in_tall_frame(false), door);
                assert_eq!(tall.bits(), door.bits(), "the packed code is unchanged");
            }
        }
        assert!(Door::NONE.in_tall_frame(true).is_none(), "no door stays none");
    }

    #[test]
    fn a_door_and_its_inverse_draw_every_pixel_exactly_once() {
        for q in 1..=3 {
            let (a, b) = (Door::quarters(q, false).unwrap(), Door::quarters(q, true).unwrap());
            let mut drawn = 0;
            for y in -8..8 {
                for x in -8..8 {
                    assert_ne!(a.hides(x, y), b.hides(x, y), "({x}, {y}) at {q} quarters");
                    drawn += i32::from(!a.hides(x, y));
                }
            }
            // In every 4x4 block, `q` quarters of the pixels.
            assert_eq!(drawn, 16 * 16 * i32::from(q) / 4);
        }
        assert_eq!((Door::quarters(0, false), Door::quarters(4, true)), (None, None));
    }

    #[test]
    fn a_growing_door_keeps_what_it_drew_and_half_is_the_checkerboard() {
        for y in 0..4 {
            for x in 0..4 {
                let drawn: Vec<bool> = (1..=3).map(|q| !Door::quarters(q, false).unwrap().hides(x, y)).collect();
                // Once a pixel is drawn by the growing door, it stays drawn (a fade never flickers back).
                assert!(drawn.windows(2).all(|w| !w[0] || w[1]), "({x}, {y}): {drawn:?}");
                assert_eq!(Door::CHECKERBOARD.hides(x, y), (x + y) & 1 != 0);
            }
        }
        assert!(!Door::NONE.hides(1, 0));
        for bits in 0..8 {
            assert_eq!(Door::from_bits(bits).bits(), if bits & 3 == 0 { 0 } else { bits });
        }
    }
}
