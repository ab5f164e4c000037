//! The band's coverage samples: pixels an edge crosses keep a colour per sample (and a depth per sample, or
//! the samples already drawn), the others stay one colour in the band's own buffers.
//!
//! Most pixels of a frame lie inside one polygon, and storing every sample of every pixel would make each
//! of them cost as much as the few an edge crosses. So a pixel starts *simple*: its colour, depth and
//! coverage bit live where the non-anti-aliased fill keeps them, and the fast span loops draw it as they
//! always do. The first polygon to cover only some of its samples *expands* it: its samples get a record in
//! the band's pool, and a mark the fast loops stop at (a depth of `+inf`, which no depth passes, or the
//! coverage bit set). A later polygon covering all its samples with one colour folds it back to simple.
//! At the end of the band every pixel still expanded is resolved to the mean of its samples.
//!
//! Per visibility method:
//! - depth test (MSAA): a colour and a depth per sample, each sample tested on its own depth (the plane's
//!   value at the sample); a simple pixel's samples take its centre depth when it expands;
//! - coverage (the seed's near-to-far order with its "already drawn" flag per sample, an A-buffer without
//!   depth): the samples drawn so far and the sum of their colours, so each sample is shaded at most once;
//!   the samples never drawn take the background (what the band held) when resolved;
//! - overwrite (painter's order): a colour per sample, overwritten by each polygon covering it.

use super::row::{SpanCounts, Visibility};
use super::sample_lanes as lanes;
use crate::render::core::samples::{MAX_SAMPLES, SamplePattern};

/// A band's expanded pixels, kept per thread and reused band after band.
///
/// An expanded pixel `k` owns samples `k * count..(k + 1) * count` of `colors` and `depths`, and entry `k`
/// of `drawn` and `sums`: only as many samples as the pattern has are stored and cleared.
#[derive(Debug, Default)]
pub(crate) struct SampleStore {
    /// Per band pixel: 0 when simple, else 1 + its index among the expanded pixels.
    slot: Vec<u32>,
    /// Colour per sample (depth test, overwrite).
    colors: Vec<u32>,
    /// Depth per sample (depth test).
    depths: Vec<f32>,
    /// The samples drawn (coverage).
    drawn: Vec<u16>,
    /// Sum of the drawn samples' channels, red, green, blue (coverage).
    sums: Vec<[u32; 3]>,
    /// Per band row: how many of its pixels were ever expanded (0: nothing to fix up or resolve).
    row_expanded: Vec<u32>,
    count: usize,
    full: u16,
}

/// A pixel of the band being drawn, its buffers and the polygon's view of it.
pub(crate) struct Pixel<'a> {
    /// Index into the band's buffers.
    pub(crate) index: usize,
    /// Band row.
    pub(crate) row: usize,
    /// The band's colour, depth and coverage bit of this pixel.
    pub(crate) color: &'a mut u32,
    pub(crate) depth: Option<&'a mut f32>,
    pub(crate) covered: Option<(&'a mut u64, u64)>,
}

impl SampleStore {
    /// Empties the store for a band of `pixels` pixels in `rows` rows with `pattern`'s samples.
    pub(crate) fn begin(&mut self, pixels: usize, rows: usize, pattern: &SamplePattern) {
        self.slot.clear();
        self.slot.resize(pixels, 0);
        self.colors.clear();
        self.depths.clear();
        self.drawn.clear();
        self.sums.clear();
        self.row_expanded.clear();
        self.row_expanded.resize(rows, 0);
        self.count = pattern.count.min(MAX_SAMPLES);
        self.full = pattern.full();
    }

    /// Whether band row `row` has had an expanded pixel (the inner runs of polygons then look for them).
    #[inline]
    pub(crate) fn row_has_expanded(&self, row: usize) -> bool {
        self.row_expanded.get(row).is_some_and(|&n| n > 0)
    }

    /// The first expanded band pixel in `range`, if any: eight slots at a time, as most runs have none.
    #[inline]
    pub(crate) fn next_expanded(&self, range: std::ops::Range<usize>) -> Option<usize> {
        let start = range.start;
        let slots = self.slot.get(range)?;
        let mut chunks = slots.chunks_exact(8);
        let mut base = start;
        for c in chunks.by_ref() {
            if c.iter().fold(0, |a, &s| a | s) != 0 {
                return c.iter().position(|&s| s != 0).map(|i| base + i);
            }
            base += 8;
        }
        chunks.remainder().iter().position(|&s| s != 0).map(|i| base + i)
    }

    /// Draws one polygon's samples `mask` of a pixel under `vis`, for a pattern of `N` samples: the polygon's
    /// depth is `centre` at the pixel's centre and `centre + dz[j]` at sample `j`, and `shade()` gives its
    /// colour there (`None` where its alpha cutoff drops it), called at most once.
    ///
    /// `N` is a constant so that the loops over a pixel's samples unroll and vectorise.
    // long: the three visibility methods' cases of one pixel, simple or expanded, side by side
    pub(crate) fn draw<const N: usize>(
        &mut self,
        px: Pixel<'_>,
        mask: u16,
        vis: Visibility,
        (centre, dz): (f32, &[f32; N]),
        shade: impl FnOnce() -> Option<u32>,
    ) -> SpanCounts {
        debug_assert_eq!(self.count, N, "a store begun for {} samples drawn with {N}", self.count);
        let (n, full) = (N, self.full);
        let rejected = SpanCounts { rejected: 1, ..SpanCounts::default() };
        let drawn = SpanCounts { shaded: 1, written: 1, rejected: 0 };
        let dropped = SpanCounts { shaded: 1, ..SpanCounts::default() };
        let slot = self.slot.get(px.index).copied().unwrap_or(0);
        let nearer = |mask: u16, old: &[f32; N]| lanes::nearer(mask, centre, dz, old);
        if slot == 0 {
            // A simple pixel.
            let (pass, old_depth) = match (vis, &px.depth, &px.covered) {
                (Visibility::DepthTest, Some(d), _) => {
                    let old = **d;
                    (nearer(mask, &[old; N]), old)
                }
                (Visibility::Coverage, _, Some((w, bit))) if **w & bit != 0 => (0, 0.0),
                _ => (mask, 0.0),
            };
            if pass == 0 {
                return rejected;
            }
            let Some(c) = shade() else { return dropped };
            if pass == full {
                *px.color = c;
                if let Some(d) = px.depth {
                    *d = centre;
                }
                if let Some((w, bit)) = px.covered {
                    *w |= bit;
                }
                return drawn;
            }
            // Expand: every sample starts as the pixel was.
            let k = self.drawn.len();
            match vis {
                Visibility::Coverage => {}
                Visibility::DepthTest => {
                    self.colors.extend(std::iter::repeat_n(*px.color, n));
                    self.depths.extend(std::iter::repeat_n(old_depth, n));
                }
                Visibility::Overwrite => self.colors.extend(std::iter::repeat_n(*px.color, n)),
            }
            self.drawn.push(0);
            self.sums.push([0; 3]);
            if let Some(s) = self.slot.get_mut(px.index) {
                *s = k as u32 + 1;
            }
            if let Some(r) = self.row_expanded.get_mut(px.row) {
                *r += 1;
            }
            self.write::<N>(k, pass, c, (centre, dz), vis);
            // The marks the fast loops stop at.
            if let Some(d) = px.depth {
                *d = f32::INFINITY;
            }
            if let Some((w, bit)) = px.covered {
                *w |= bit;
            }
            return drawn;
        }
        let k = slot as usize - 1;
        let pass = match vis {
            Visibility::DepthTest => {
                let Some(depths) = self.depths.get(k * n..(k + 1) * n).and_then(|d| <&[f32; N]>::try_from(d).ok())
                else {
                    return rejected;
                };
                nearer(mask, depths)
            }
            Visibility::Coverage => mask & !self.drawn.get(k).copied().unwrap_or(full),
            Visibility::Overwrite => mask,
        };
        if pass == 0 {
            return rejected;
        }
        let Some(c) = shade() else { return dropped };
        self.write::<N>(k, pass, c, (centre, dz), vis);
        let fold = match vis {
            Visibility::Coverage => self.drawn.get(k) == Some(&full),
            Visibility::DepthTest | Visibility::Overwrite => pass == full,
        };
        if fold {
            // One colour again (or, for coverage, every sample drawn): simple from now on.
            *px.color = match (vis, self.sums.get(k)) {
                (Visibility::Coverage, Some(&sum)) => mean(sum, n),
                _ => c,
            };
            if let Some(d) = px.depth {
                *d = centre;
            }
            if let Some(s) = self.slot.get_mut(px.index) {
                *s = 0;
            }
        }
        drawn
    }

    /// Gives samples `pass` of expanded pixel `k` colour `c` (and their depths, or marks them drawn).
    #[inline]
    fn write<const N: usize>(&mut self, k: usize, pass: u16, c: u32, (centre, dz): (f32, &[f32; N]), vis: Visibility) {
        let n = N;
        match vis {
            Visibility::Coverage => {
                if let (Some(d), Some(sum)) = (self.drawn.get_mut(k), self.sums.get_mut(k)) {
                    *d |= pass;
                    add_to_sum(sum, c, pass.count_ones());
                }
            }
            Visibility::DepthTest | Visibility::Overwrite => {
                if let Some(colors) =
                    self.colors.get_mut(k * n..(k + 1) * n).and_then(|s| <&mut [u32; N]>::try_from(s).ok())
                {
                    lanes::write_colour(colors, pass, c);
                }
                if vis == Visibility::DepthTest
                    && let Some(depths) =
                        self.depths.get_mut(k * n..(k + 1) * n).and_then(|s| <&mut [f32; N]>::try_from(s).ok())
                {
                    lanes::write_depth(depths, pass, centre, dz);
                }
            }
        }
    }

    /// Resolves every pixel still expanded in band row `row` (pixels `row * width..`) into `color`: the
    /// mean of its samples (coverage: the samples never drawn count as the colour the pixel held).
    pub(crate) fn resolve_row<const N: usize>(&self, row: usize, width: usize, color: &mut [u32], vis: Visibility) {
        if !self.row_has_expanded(row) {
            return;
        }
        let n = N;
        let start = row * width;
        let (Some(slots), Some(colors)) = (self.slot.get(start..start + width), color.get_mut(start..start + width))
        else {
            return;
        };
        for (&s, c) in slots.iter().zip(colors) {
            if s == 0 {
                continue;
            }
            let k = s as usize - 1;
            let mut sum = [0u32; 3];
            if vis == Visibility::Coverage {
                let (Some(&drawn), Some(&drawn_sum)) = (self.drawn.get(k), self.sums.get(k)) else { continue };
                sum = drawn_sum;
                add_to_sum(&mut sum, *c, n as u32 - drawn.count_ones());
            } else if let Some(colors) = self.colors.get(k * n..(k + 1) * n).and_then(|s| <&[u32; N]>::try_from(s).ok())
            {
                sum = lanes::channel_sums(colors);
            }
            *c = mean(sum, n);
        }
    }
}

/// Adds `weight` times the channels of `c` to `sum`.
#[inline]
fn add_to_sum(sum: &mut [u32; 3], c: u32, weight: u32) {
    sum[0] += ((c >> 16) & 0xff) * weight;
    sum[1] += ((c >> 8) & 0xff) * weight;
    sum[2] += (c & 0xff) * weight;
}

/// The packed colour of channel sums over `n` samples, rounded to nearest.
#[inline]
fn mean(sum: [u32; 3], n: usize) -> u32 {
    let n = n.max(1) as u32;
    let ch = |s: u32| ((s + n / 2) / n).min(255);
    (ch(sum[0]) << 16) | (ch(sum[1]) << 8) | ch(sum[2])
}
