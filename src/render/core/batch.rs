//! What polygon set-up hands to the fill: batches of screen vertices, small triangles and polygons, and
//! where the z-buffer's drawing order finds them.

use std::ops::Range;

use super::polygon::DrawPolygon;
use super::small::{SmallTriangle, TexPlanes};
use super::stats::Stats;
use super::vertex::ScreenVertex;

/// Polygons dropped or changed during set-up, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Counts {
    pub(crate) invalid: u64,
    pub(crate) outside: u64,
    pub(crate) clipped: u64,
    pub(crate) degenerate: u64,
    pub(crate) backface: u64,
    pub(crate) drawn: u64,
    pub(crate) split: u64,
}

impl Counts {
    /// The polygon counts of a frame's statistics.
    fn from_stats(s: &Stats) -> Self {
        Self {
            invalid: s.polygons_invalid,
            outside: s.polygons_outside,
            clipped: s.polygons_clipped,
            degenerate: s.polygons_degenerate,
            backface: s.polygons_backface,
            drawn: s.polygons_drawn,
            split: s.polygons_split,
        }
    }

    /// Adds these counts to a frame's statistics.
    pub(crate) fn add_to(&self, stats: &mut Stats) {
        stats.polygons_invalid += self.invalid;
        stats.polygons_outside += self.outside;
        stats.polygons_clipped += self.clipped;
        stats.polygons_degenerate += self.degenerate;
        stats.polygons_backface += self.backface;
        stats.polygons_drawn += self.drawn;
        stats.polygons_split += self.split;
    }
}

/// Set-up output (screen vertices, small triangles and the polygons indexing them) and the scratch buffers
/// that make it.
#[derive(Debug, Default)]
pub(crate) struct Batch {
    pub(crate) screen: Vec<ScreenVertex>,
    /// Flat small triangles set up for the fast path, in place of their screen vertices.
    pub(crate) small: Vec<SmallTriangle>,
    /// Textured ones, with their texture planes.
    pub(crate) small_textured: Vec<(SmallTriangle, TexPlanes)>,
    pub(crate) polys: Vec<DrawPolygon>,
    /// The polygons' ordering keys, one each, when the frame is ordered by them (empty for the z-buffer:
    /// see [`ObjectSetup::ordered`](crate::render::geometry::setup::ObjectSetup::ordered)).
    pub(crate) keys: Vec<f32>,
    pub(crate) counts: Counts,
    /// For each band, the indices of its polygons touching the band, when it binned them itself (the
    /// z-buffer's set-up pieces: see [`crate::render::fill::bands::BinnedRun`]); unused in the main batch.
    pub(crate) bins: Vec<Vec<u32>>,
    /// The number its polygons carry in [`DrawPolygon::batch`] (see [`Screens`]): 0 for the main batch.
    pub(crate) tag: u32,
}

impl Batch {
    /// Stores a small triangle's set-up (with its texture planes when `textured`); returns its index.
    #[inline]
    pub(crate) fn push_small(&mut self, (t, planes): (SmallTriangle, TexPlanes), textured: bool) -> u32 {
        if textured {
            self.small_textured.push((t, planes));
            self.small_textured.len() as u32 - 1
        } else {
            self.small.push(t);
            self.small.len() as u32 - 1
        }
    }

    /// Empties the output, keeping the allocations.
    pub(crate) fn clear(&mut self) {
        self.screen.clear();
        self.small.clear();
        self.small_textured.clear();
        self.polys.clear();
        self.keys.clear();
        self.counts = Counts::default();
    }

    /// Appends the polygons of `others` to this batch, in order (each was tagged with its batch's number
    /// when it was set up); their screen vertices stay where they are, found through [`Screens`].
    ///
    /// Only the polygon records move: copying the screen vertices too (megabytes on a scene of many small
    /// polygons) costs more than setting up in parallel saves, and as each polygon already carries its
    /// batch's number from set-up, appending them is a plain copy (a memcpy), not a pass that re-tags them.
    pub(crate) fn adopt_polygons(&mut self, others: &[Batch]) {
        for b in others {
            self.polys.extend_from_slice(&b.polys);
            self.keys.extend_from_slice(&b.keys);
        }
        self.adopt_counts(others);
    }

    /// Adds the set-up counts of `others` to this batch's, leaving their polygons where they are.
    pub(crate) fn adopt_counts(&mut self, others: &[Batch]) {
        let mut stats = Stats::default();
        self.counts.add_to(&mut stats);
        for b in others {
            b.counts.add_to(&mut stats);
        }
        self.counts = Counts::from_stats(&stats);
    }
}

/// Where the screen vertices (or small triangles) of a frame's polygons are: batch 0 is the main batch,
/// batch `k` the set-up batch `k - 1`.
#[derive(Clone, Copy)]
pub(crate) struct Screens<'a> {
    /// The main batch.
    pub(crate) main: &'a Batch,
    /// The set-up batches of big objects, whose vertices were left in place.
    pub(crate) batches: &'a [Batch],
}

impl<'a> Screens<'a> {
    /// The batch holding polygon `p`'s corners.
    #[inline(always)]
    fn batch(&self, p: &DrawPolygon) -> Option<&'a Batch> {
        match p.batch {
            0 => Some(self.main),
            k => self.batches.get(k as usize - 1),
        }
    }

    /// The screen vertices of polygon `p` (`None` for a small triangle, or a polygon whose indices are out
    /// of range).
    #[inline(always)]
    pub(crate) fn of(&self, p: &DrawPolygon) -> Option<&'a [ScreenVertex]> {
        if p.small() {
            return None;
        }
        self.batch(p)?.screen.get(p.first as usize..(p.first + p.count) as usize)
    }

    /// The set-up of small triangle `p` and its texture planes ([`TexPlanes::NONE`] when it has no
    /// texture); `None` if `p` is not one.
    #[inline(always)]
    pub(crate) fn small(&self, p: &DrawPolygon) -> Option<(&'a SmallTriangle, &'a TexPlanes)> {
        if !p.small() {
            return None;
        }
        let b = self.batch(p)?;
        if p.texture().is_some() {
            b.small_textured.get(p.first as usize).map(|(t, planes)| (t, planes))
        } else {
            b.small.get(p.first as usize).map(|t| (t, &TexPlanes::NONE))
        }
    }
}

/// Where a stretch of the z-buffer's drawing order is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Stretch {
    /// Polygons `range` of the main batch, binned by the fill stage.
    Main(Range<u32>),
    /// All the polygons of set-up batch `k`, binned by its set-up.
    Batch(usize),
}
