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
use crate::render::core::samples::{MAX_SAMPLES, SamplePattern};

/// An expanded pixel's samples.
#[derive(Clone, Copy, Debug)]
struct Expanded {
    /// Colour per sample (depth test, overwrite).
    color: [u32; MAX_SAMPLES],
    /// Depth per sample (depth test).
    depth: [f32; MAX_SAMPLES],
    /// The samples drawn (coverage).
    drawn: u16,
    /// Sum of the drawn samples' channels, red, green, blue (coverage).
    sum: [u32; 3],
}

/// A band's expanded pixels, kept per thread and reused band after band.
#[derive(Debug, Default)]
pub(crate) struct SampleStore {
    /// Per band pixel: 0 when simple, else 1 + its index in `pool`.
    slot: Vec<u32>,
    pool: Vec<Expanded>,
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
        self.pool.clear();
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

    /// Whether band pixel `index` is expanded.
    #[inline]
    pub(crate) fn is_expanded(&self, index: usize) -> bool {
        self.slot.get(index).is_some_and(|&s| s != 0)
    }

    /// Draws one polygon's samples `mask` of a pixel under `vis`: `depth(j)` is the polygon's depth at
    /// sample `j`, `centre` at the pixel's centre, and `shade()` its colour there (`None` where its alpha
    /// cutoff drops it), called at most once.
    // long: the three visibility methods' cases of one pixel, simple or expanded, side by side
    pub(crate) fn draw(
        &mut self,
        px: Pixel<'_>,
        mask: u16,
        vis: Visibility,
        (centre, depth): (f32, &[f32; MAX_SAMPLES]),
        shade: impl FnOnce() -> Option<u32>,
    ) -> SpanCounts {
        let (n, full) = (self.count, self.full);
        let rejected = SpanCounts { rejected: 1, ..SpanCounts::default() };
        let drawn = SpanCounts { shaded: 1, written: 1, rejected: 0 };
        let dropped = SpanCounts { shaded: 1, ..SpanCounts::default() };
        let slot = self.slot.get(px.index).copied().unwrap_or(0);
        let samples = |m: u16| (0..n).filter(move |j| m >> j & 1 == 1);
        if slot == 0 {
            // A simple pixel.
            let (pass, old_depth) = match (vis, &px.depth, &px.covered) {
                (Visibility::DepthTest, Some(d), _) => {
                    let old = **d;
                    (samples(mask).filter(|&j| depth[j] > old).fold(0u16, |m, j| m | 1 << j), old)
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
            let mut e =
                Expanded { color: [*px.color; MAX_SAMPLES], depth: [old_depth; MAX_SAMPLES], drawn: 0, sum: [0; 3] };
            for j in samples(pass) {
                e.color[j] = c;
                e.depth[j] = depth[j];
            }
            e.drawn = pass;
            add_to_sum(&mut e.sum, c, pass.count_ones());
            self.pool.push(e);
            if let Some(s) = self.slot.get_mut(px.index) {
                *s = self.pool.len() as u32;
            }
            if let Some(r) = self.row_expanded.get_mut(px.row) {
                *r += 1;
            }
            // The marks the fast loops stop at.
            if let Some(d) = px.depth {
                *d = f32::INFINITY;
            }
            if let Some((w, bit)) = px.covered {
                *w |= bit;
            }
            return drawn;
        }
        let Some(e) = self.pool.get_mut(slot as usize - 1) else { return rejected };
        let pass = match vis {
            Visibility::DepthTest => samples(mask).filter(|&j| depth[j] > e.depth[j]).fold(0u16, |m, j| m | 1 << j),
            Visibility::Coverage => mask & !e.drawn,
            Visibility::Overwrite => mask,
        };
        if pass == 0 {
            return rejected;
        }
        let Some(c) = shade() else { return dropped };
        for j in samples(pass) {
            e.color[j] = c;
            e.depth[j] = depth[j];
        }
        e.drawn |= pass;
        add_to_sum(&mut e.sum, c, pass.count_ones());
        let fold = match vis {
            Visibility::Coverage => e.drawn == full,
            Visibility::DepthTest | Visibility::Overwrite => pass == full,
        };
        if fold {
            // One colour again (or, for coverage, every sample drawn): simple from now on.
            *px.color = if vis == Visibility::Coverage { mean(e.sum, 0, n) } else { c };
            if let Some(d) = px.depth {
                *d = centre;
            }
            if let Some(s) = self.slot.get_mut(px.index) {
                *s = 0;
            }
        }
        drawn
    }

    /// Resolves every pixel still expanded in band row `row` (pixels `row * width..`) into `color`: the
    /// mean of its samples (coverage: the samples never drawn count as the colour the pixel held).
    pub(crate) fn resolve_row(&self, row: usize, width: usize, color: &mut [u32], vis: Visibility) {
        if !self.row_has_expanded(row) {
            return;
        }
        let n = self.count;
        let start = row * width;
        let (Some(slots), Some(colors)) = (self.slot.get(start..start + width), color.get_mut(start..start + width))
        else {
            return;
        };
        for (&s, c) in slots.iter().zip(colors) {
            if s == 0 {
                continue;
            }
            let Some(e) = self.pool.get(s as usize - 1) else { continue };
            *c = if vis == Visibility::Coverage {
                let rest = n as u32 - e.drawn.count_ones();
                let mut sum = e.sum;
                add_to_sum(&mut sum, *c, rest);
                mean(sum, 0, n)
            } else {
                let mut sum = [0u32; 3];
                for &s in &e.color[..n] {
                    add_to_sum(&mut sum, s, 1);
                }
                mean(sum, 0, n)
            };
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

/// The packed colour of channel sums over `n` samples (plus `extra` in each), rounded to nearest.
#[inline]
fn mean(sum: [u32; 3], extra: u32, n: usize) -> u32 {
    let n = n.max(1) as u32;
    let ch = |s: u32| ((s + extra + n / 2) / n).min(255);
    (ch(sum[0]) << 16) | (ch(sum[1]) << 8) | ch(sum[2])
}
