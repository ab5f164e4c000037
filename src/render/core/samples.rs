//! Where a pixel's coverage samples are: the Direct3D standard patterns for 4, 8 and 16 samples, on the
//! [`Fx28_4`](super::fixed::Fx28_4) grid.
//!
//! A pixel `(x, y)` spans `[16x, 16x + 16)` in raw fixed-point units; its sample `j` sits at
//! `(16x + X[j], 16y + Y[j])`. The patterns are the standard ones (offsets from the centre in 1/16 pixel), so
//! no two samples share a row or a column for 4 and 8 samples: every edge direction sees evenly spread
//! positions. Being on the vertices' own grid, a sample's coverage is decided exactly, with the same
//! top-left rule as the pixel centres (see `fill::scanline`).

/// The most samples a pixel may have (masks are `u16`).
pub const MAX_SAMPLES: usize = 16;

/// A sample pattern: each sample's position within the pixel, in 1/16 pixel from its top-left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SamplePattern {
    /// Sample positions `(x, y)`, each in `0..16`; only the first `count` are used.
    pub positions: [(i32, i32); MAX_SAMPLES],
    /// How many samples.
    pub count: usize,
}

/// The standard offsets from the pixel centre, 1/16 pixel, for 4 samples.
const OFFSETS_4: [(i32, i32); 4] = [(-2, -6), (6, -2), (-6, 2), (2, 6)];
/// The 4-sample pattern as four rows of a frame drawn four rows a pixel (the rotated grid,
/// [`Antialias::RotatedGrid`](crate::render::Antialias::RotatedGrid)): row `4y + k` of that frame samples
/// pixel row `y` at `(2k - 3) * 2` sixteenths from its centre, that is the 4-sample pattern's `y`s in order, and
/// each of its samples lies `ROW_SHIFTS[k]` sixteenths right of its pixel's centre, the `x` of the pattern's
/// sample on that row. So the four rows of a pixel hold the pattern's four samples.
pub const ROW_SHIFTS: [i32; 4] = [-2, 6, -6, 2];

/// For 8 samples.
const OFFSETS_8: [(i32, i32); 8] = [(1, -3), (-1, 3), (5, 1), (-3, -5), (-5, 5), (-7, -1), (3, 7), (7, -7)];
/// For 16 samples.
const OFFSETS_16: [(i32, i32); 16] = [
    (1, 1),
    (-1, -3),
    (-3, 2),
    (4, -1),
    (-5, -2),
    (2, 5),
    (5, 3),
    (3, -5),
    (-2, 6),
    (0, -7),
    (-4, -6),
    (-6, 4),
    (-8, 0),
    (7, -4),
    (6, 7),
    (-7, -8),
];

impl SamplePattern {
    /// The standard pattern of `count` samples: 4, 8 or 16 (`None` for any other count).
    #[must_use]
    pub fn standard(count: usize) -> Option<Self> {
        let offsets: &[(i32, i32)] = match count {
            4 => &OFFSETS_4,
            8 => &OFFSETS_8,
            16 => &OFFSETS_16,
            _ => return None,
        };
        let mut positions = [(8, 8); MAX_SAMPLES];
        for (p, &(dx, dy)) in positions.iter_mut().zip(offsets) {
            *p = (8 + dx, 8 + dy);
        }
        Some(Self { positions, count })
    }

    /// The mask with every sample set.
    #[must_use]
    pub fn full(&self) -> u16 {
        if self.count >= 16 { u16::MAX } else { (1u16 << self.count) - 1 }
    }

    /// Sample `j`'s offset from the pixel centre in pixels.
    #[must_use]
    pub fn offset(&self, j: usize) -> (f32, f32) {
        let (x, y) = self.positions[j % MAX_SAMPLES];
        ((x - 8) as f32 / 16.0, (y - 8) as f32 / 16.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_shifts_are_the_four_sample_pattern_row_by_row() {
        let mut by_row = OFFSETS_4;
        by_row.sort_by_key(|&(_, y)| y);
        let rows: Vec<i32> = by_row.iter().map(|&(_, y)| y).collect();
        // Row 4y + k of a frame four rows a pixel has its centre (2k - 3) * 2 sixteenths from pixel y's.
        assert_eq!(rows, (0..4).map(|k| (2 * k - 3) * 2).collect::<Vec<_>>());
        assert_eq!(by_row.map(|(x, _)| x), ROW_SHIFTS);
    }

    #[test]
    fn patterns_lie_inside_the_pixel_and_spread_over_its_rows_and_columns() {
        for n in [4, 8, 16] {
            let p = SamplePattern::standard(n).unwrap();
            let used = &p.positions[..n];
            assert!(used.iter().all(|&(x, y)| (0..16).contains(&x) && (0..16).contains(&y)));
            let mut xs: Vec<i32> = used.iter().map(|p| p.0).collect();
            let mut ys: Vec<i32> = used.iter().map(|p| p.1).collect();
            xs.sort_unstable();
            ys.sort_unstable();
            xs.dedup();
            ys.dedup();
            // 4 and 8 samples: every sample on its own row and column (16: at least 14 distinct each).
            assert!(xs.len() >= n.min(14) && ys.len() >= n.min(14), "{n}: {xs:?} {ys:?}");
            let mean = used.iter().fold((0, 0), |a, p| (a.0 + p.0 - 8, a.1 + p.1 - 8));
            assert!(mean.0.abs() <= n as i32 && mean.1.abs() <= n as i32, "{n}: centred, {mean:?}");
            assert_eq!(p.full().count_ones() as usize, n);
        }
        assert!(SamplePattern::standard(3).is_none());
    }
}
