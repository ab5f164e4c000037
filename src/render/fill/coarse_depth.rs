//! A band's coarse depth: for each tile of [`TILE_ROWS`] x [`TILE_COLUMNS`] pixels, a floor under the
//! depths stored in it, so that a polygon nearer than no floor it overlaps is skipped whole, without
//! walking its edges or testing its pixels.
//!
//! Why: on the city's frames a third of the depth-tested pixels fail the test and many more are drawn over
//! (buildings drawn after and before what they hide), most of them of polygons of which no pixel is left in
//! the band at its end; each of them still costs the walk of its edges and a depth test per chunk.
//!
//! **Floors** come from the band's whole bin before its first polygon is drawn: a convex polygon that
//! writes every pixel it covers and passes (no alpha cutoff, no screen door) raises the floor of each tile
//! it covers whole (by [`INSIDE`] pixels) to its least corner depth less a margin. Small triangles and
//! cut-outs raise none, which leaves floors lower than they could be but never wrong.
//!
//! **What is skipped**, a tile at a time: a polygon whose tiles all hide it, whole; the rows of tiles at its
//! top and bottom that hide it ([`BandTest::rows`]); and, when some tile between them hides it too, each
//! span's pixels in such tiles ([`Behind::columns`]): a span whole, else the chunks before and after.
//!
//! **Exactness.** A pixel is written only when its depth is strictly greater (nearer) than the stored
//! one, so a band's final depth at a pixel is the greatest any polygon gives it, and its colour that of the
//! first polygon to give it: a polygon strictly below that greatest at each of its pixels changes neither,
//! and skipping it changes no pixel, no depth and no colour. A tile's floor was raised by a polygon that
//! covers it whole and writes every pixel it passes, and every pixel of the tile ends at a depth at least
//! the floor, because that polygon is drawn over the whole tile, before or after any other: it is skipped,
//! whole or there, only where a floor is strictly above its greatest depth, and the floor it raised is at
//! most that (equal only for a polygon whose corners are all at depth 0). So a polygon whose greatest depth
//! is strictly below the floor of every tile its pixels can fall in is strictly below the final depth
//! everywhere, and is skipped (and so is its pixel in a tile whose floor is strictly above that depth). Its
//! depth is affine on the screen, so over its pixels it is at most its corners' greatest; the fill's
//! interpolation rounds, and a span narrower than a pixel extrapolates its edges' rounding by up to 64
//! times its width, so the bound is raised by a margin ([`margin`]) well above both. Its pixels lie in the
//! box of its corners widened by a pixel each way (which holds the rotated grid's shifted samples too).
//! Floors come only from corner depths under 2^64 in magnitude, whose slopes the fill's arithmetic holds
//! without overflow (a pixel given an infinite or NaN depth is never written).
//! A NaN or infinite corner depth is never skipped.
//!
//! The frame's statistics do not count what is skipped (its pixels neither shaded, written nor rejected),
//! so they depend on the band layout (the thread count) and on which bands were tried.

use std::sync::atomic::{AtomicU8, Ordering};

use crate::render::core::vertex::ScreenVertex;

/// Frames a band goes without the test after a frame where it hid too few polygons there ([`PAYS`]),
/// before trying again.
const REST: u8 = 7;

/// The test pays in a band where it hides at least one polygon in this many tried: a hidden polygon saves
/// the walk of its edges and its chunks' depth tests, some ten times what trying one costs.
const PAYS: u32 = 16;

/// One band's use of the coarse depth while its polygons are drawn, and its memory from frame to frame.
///
/// Where the test hides few polygons in a band (a view across open ground, where little is drawn behind
/// what was), its cost is overhead, 3-4% of the mountain's and the circuit's frames: the band then rests
/// [`REST`] frames before it is tried again. What a band remembers changes only what is tried, never a
/// pixel.
pub(crate) struct BandTest<'s> {
    coarse: &'s mut CoarseDepth,
    memory: Option<&'s AtomicU8>,
    on: bool,
    /// Polygons tried and hidden.
    tried: u32,
    hidden: u32,
    band: (i32, i32),
}

impl<'s> BandTest<'s> {
    /// Starts band rows `band` (frame rows) of a frame `width` wide, with what the band remembers
    /// (`memory`): tested only when depth-tested and not resting.
    pub(crate) fn begin(
        coarse: &'s mut CoarseDepth,
        memory: Option<&'s AtomicU8>,
        depth_tested: bool,
        band: (i32, i32),
        width: usize,
    ) -> Self {
        let rest = memory.map_or(0, |m| m.load(Ordering::Relaxed));
        let on = depth_tested && rest == 0;
        if on {
            coarse.begin(width, (band.1 - band.0).max(0) as usize);
        } else if let Some(m) = memory {
            m.store(rest.saturating_sub(1), Ordering::Relaxed);
        }
        Self { coarse, memory, on, tried: 0, hidden: 0, band }
    }

    /// Whether the band is tried this frame (depth-tested and not resting).
    #[inline]
    pub(crate) fn on(&self) -> bool {
        self.on
    }

    /// Raises the floors by `polygons` (their corners), the band's polygons that write every pixel they
    /// cover and pass (no alpha cutoff, no screen door), before any polygon of the band is drawn.
    pub(crate) fn cover_all<'v>(&mut self, polygons: impl Iterator<Item = &'v [ScreenVertex]>) {
        if !self.on {
            return;
        }
        for verts in polygons {
            if let Some((_, b)) = reach(verts, self.band, self.coarse.width) {
                self.coarse.cover(verts, self.band, &b);
            }
        }
    }

    /// The frame rows polygon `verts` is drawn on: the band's, less the rows of tiles at its top and
    /// bottom whose floors hide it wherever it can fall in them, and the floors it lies behind in some tile
    /// between them (none when it lies behind none); `None` when they hide it whole: skip it.
    #[inline]
    pub(crate) fn rows(&mut self, verts: &[ScreenVertex]) -> Option<((i32, i32), Option<Behind<'_>>)> {
        let Some((z, b)) = reach(verts, self.band, self.coarse.width).filter(|_| self.on) else {
            return Some((self.band, None));
        };
        self.tried += 1;
        let Some(((r0, r1), partly)) = self.coarse.unhidden_rows(&b, z) else {
            self.hidden += 1;
            return None;
        };
        let rows = ((self.band.0 + r0 as i32).max(self.band.0), (self.band.0 + r1 as i32).min(self.band.1));
        let c = &*self.coarse;
        Some((rows, partly.then_some(Behind { floor: &c.floor, tiles_x: c.tiles_x, band0: self.band.0, z })))
    }

    /// Ends the band: it rests when tested and it hid fewer than one polygon in [`PAYS`] tried.
    pub(crate) fn end(self) {
        if let (true, Some(m)) = (self.on, self.memory) {
            let paid = u64::from(self.hidden) * u64::from(PAYS) >= u64::from(self.tried);
            m.store(if paid { 0 } else { REST }, Ordering::Relaxed);
        }
    }
}

/// The floors a polygon drawn on a band may lie behind, with its greatest depth: which columns of a row
/// its pixels may pass the depth test in.
#[derive(Clone, Copy)]
pub(crate) struct Behind<'c> {
    floor: &'c [f32],
    tiles_x: usize,
    /// The band's first frame row.
    band0: i32,
    /// The greatest depth the polygon gives a pixel ([`reach`]).
    z: f32,
}

impl<'c> Behind<'c> {
    /// Floors `floor` of a band starting at frame row `band0`, `tiles_x` tiles a row, for a polygon of
    /// greatest depth `z`.
    #[cfg(test)]
    pub(crate) fn of(floor: &'c [f32], tiles_x: usize, band0: i32, z: f32) -> Self {
        Self { floor, tiles_x, band0, z }
    }

    /// The columns `from..to` of the polygon's span `x0..x1` on frame row `y` outside of which every tile
    /// hides it, a tile at a time; `None` when every tile under the span does: it passes the test nowhere.
    #[inline]
    pub(crate) fn columns(&self, y: i32, (x0, x1): (usize, usize)) -> Option<(usize, usize)> {
        let ty = (y - self.band0).max(0) as usize / TILE_ROWS;
        let (t0, t1) = (x0 / TILE_COLUMNS, x1.saturating_sub(1) / TILE_COLUMNS + 1);
        let Some(row) = self.floor.get(ty * self.tiles_x + t0..ty * self.tiles_x + t1) else { return Some((x0, x1)) };
        let first = row.iter().position(|&f| self.z >= f)?;
        let last = row.iter().rposition(|&f| self.z >= f).unwrap_or(first);
        Some((x0.max((t0 + first) * TILE_COLUMNS), x1.min((t0 + last + 1) * TILE_COLUMNS)))
    }
}

/// Rows of a tile.
pub(crate) const TILE_ROWS: usize = 8;
/// Columns of a tile.
pub(crate) const TILE_COLUMNS: usize = 16;

/// The pixels a polygon's samples can fall in on a band, as band rows and frame columns (end exclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Box2 {
    pub(crate) rows: (usize, usize),
    pub(crate) columns: (usize, usize),
}

/// What bounds every depth the fill interpolates for a polygon's pixels, given its corners' depths' range
/// `least..=greatest` and their largest magnitude `largest`: `greatest` raised by a 2^-10 part of `largest`
/// (one rounding is 2^-24 of it, and a pixel's depth takes fewer than ten) and an eighth of the range (a span
/// under a pixel wide steps its depth by up to 64 times its change across the span, and its edges come with
/// up to 10^-3 pixel of rounding: at most 6.4% of the range beyond it).
#[inline]
fn margin(least: f32, greatest: f32, largest: f32) -> f32 {
    greatest + largest * (1.0 / 1024.0) + (greatest - least) * 0.125
}

/// The greatest depth polygon `verts` can give a pixel and the box its pixels lie in on band rows
/// `band` (frame rows) of a frame `width` wide; `None` when a corner's depth is NaN or infinite or the box
/// is empty.
#[inline]
pub(crate) fn reach(verts: &[ScreenVertex], band: (i32, i32), width: usize) -> Option<(f32, Box2)> {
    let first = verts.first()?;
    let (low, z, largest) = depths(verts)?;
    let (mut x0, mut x1, mut y0, mut y1) = (first.x.0, first.x.0, first.y.0, first.y.0);
    for v in verts {
        (x0, x1) = (x0.min(v.x.0), x1.max(v.x.0));
        (y0, y1) = (y0.min(v.y.0), y1.max(v.y.0));
    }
    // Whole pixels around the corners, one more each way (raw units are sixteenths).
    let pixel = |raw: i32, grow: i32| i64::from(raw >> 4) + i64::from(grow);
    let clamp = |v: i64, lo: i64, hi: i64| v.clamp(lo, hi);
    let (c0, c1) = (clamp(pixel(x0, -1), 0, width as i64), clamp(pixel(x1, 2), 0, width as i64));
    let (b0, b1) = (i64::from(band.0), i64::from(band.1));
    let (r0, r1) = (clamp(pixel(y0, -1), b0, b1), clamp(pixel(y1, 2), b0, b1));
    if c0 >= c1 || r0 >= r1 {
        return None;
    }
    let rows = ((r0 - b0) as usize, (r1 - b0) as usize);
    Some((margin(low, z, largest), Box2 { rows, columns: (c0 as usize, c1 as usize) }))
}

/// The floors of one band's tiles, reused band after band.
#[derive(Debug, Default)]
pub(crate) struct CoarseDepth {
    width: usize,
    rows: usize,
    tiles_x: usize,
    /// Each tile's floor, row of tiles after row of tiles.
    floor: Vec<f32>,
    /// The greatest floor: a polygon nearer than it somewhere is hidden by no tile, found without a look at
    /// any (on a band where nothing has covered a tile yet, every polygon).
    top: f32,
}

impl CoarseDepth {
    /// Starts a band of `rows` rows `width` pixels wide whose depths are all `-inf`.
    pub(crate) fn begin(&mut self, width: usize, rows: usize) {
        self.width = width;
        self.rows = rows;
        self.tiles_x = width.div_ceil(TILE_COLUMNS);
        let n = self.tiles_x * rows.div_ceil(TILE_ROWS);
        self.floor.clear();
        self.floor.resize(n, f32::NEG_INFINITY);
        self.top = f32::NEG_INFINITY;
    }

    /// The tiles box `b` overlaps: rows of tiles and columns of tiles (end exclusive).
    #[inline]
    fn tiles(&self, b: &Box2) -> ((usize, usize), (usize, usize)) {
        let ty = (b.rows.0 / TILE_ROWS, b.rows.1.div_ceil(TILE_ROWS));
        let tx = (b.columns.0 / TILE_COLUMNS, b.columns.1.div_ceil(TILE_COLUMNS));
        (ty, tx)
    }

    /// The band rows `r0..r1` outside of which every pixel in box `b` holds a depth above `z` (by the
    /// floors), rows of tiles at a time, and whether some tile between them does too; `None` when every
    /// pixel in the box does: then a polygon of greatest depth `z` inside the box passes the test nowhere,
    /// and one drawn on rows `r0..r1` nowhere else.
    #[inline]
    pub(crate) fn unhidden_rows(&self, b: &Box2, z: f32) -> Option<((usize, usize), bool)> {
        // `z` is finite (`reach`), and so is every floor raised.
        if z >= self.top {
            return Some(((0, self.rows), false));
        }
        let (ty, tx) = self.tiles(b);
        let floors = |y: usize| self.floor.get(y * self.tiles_x + tx.0..y * self.tiles_x + tx.1).unwrap_or(&[]);
        let hides = |y: usize| {
            let row = floors(y);
            !row.is_empty() && row.iter().all(|&f| z < f)
        };
        let first = (ty.0..ty.1).find(|&y| !hides(y))?;
        let last = (first..ty.1).rfind(|&y| !hides(y)).unwrap_or(first);
        let partly = (first..=last).any(|y| floors(y).iter().any(|&f| z < f));
        Some(((first * TILE_ROWS, ((last + 1) * TILE_ROWS).min(self.rows)), partly))
    }

    /// Whether every pixel in box `b` holds a depth above `z` (by the floors): then a polygon of greatest
    /// depth `z` inside the box passes the test nowhere.
    #[cfg(test)]
    pub(crate) fn hidden(&self, b: &Box2, z: f32) -> bool {
        self.unhidden_rows(b, z).is_none()
    }

    /// Raises the floors of the tiles polygon `verts` covers whole to its least depth (less a margin), for
    /// a polygon of band rows `band` (frame rows) with box `b` that will be drawn: every pixel of such a tile
    /// will end at the polygon's depth or a greater one. Only for a convex polygon that writes every pixel it
    /// covers and passes (no alpha cutoff, no screen door: the caller checks).
    pub(crate) fn cover(&mut self, verts: &[ScreenVertex], band: (i32, i32), b: &Box2) {
        // The tiles wholly inside the box, the only ones the polygon can cover.
        let ty = (b.rows.0.div_ceil(TILE_ROWS), (b.rows.1 / TILE_ROWS + usize::from(b.rows.1 == self.rows)));
        let tx =
            (b.columns.0.div_ceil(TILE_COLUMNS), (b.columns.1 / TILE_COLUMNS + usize::from(b.columns.1 == self.width)));
        let (ty, tx) = ((ty.0, ty.1.min(self.rows.div_ceil(TILE_ROWS))), (tx.0, tx.1.min(self.tiles_x)));
        if ty.0 >= ty.1 || tx.0 >= tx.1 {
            return;
        }
        let Some(least) = least_depth(verts) else { return };
        // Nothing to raise unless some floor there is below the polygon's least depth.
        let below = (ty.0..ty.1).any(|y| {
            let row = self.floor.get(y * self.tiles_x + tx.0..y * self.tiles_x + tx.1).unwrap_or(&[]);
            row.iter().any(|&f| f < least)
        });
        if !below {
            return;
        }
        let Some(shape) = Convex::of(verts) else { return };
        for y in ty.0..ty.1 {
            let r0 = f64::from(band.0) + (y * TILE_ROWS) as f64;
            let r1 = f64::from(band.0) + ((y + 1) * TILE_ROWS).min(self.rows) as f64;
            let Some((left, right)) = shape.columns((r0, r1)) else { continue };
            // The tiles whose columns lie within `left..right`.
            let x0 = (left / TILE_COLUMNS as f64).ceil().max(tx.0 as f64) as usize;
            let x1 = (right / TILE_COLUMNS as f64).floor().min(tx.1 as f64) as usize;
            if x0 >= x1 {
                continue;
            }
            for floor in self.floor.get_mut(y * self.tiles_x + x0..y * self.tiles_x + x1).unwrap_or(&mut []) {
                *floor = floor.max(least);
            }
            self.top = self.top.max(least);
        }
    }
}

/// The least depth polygon `verts` can give a pixel of a tile it covers whole (its least corner depth less
/// a 2^-10 part of the largest magnitude, far above the rounding: such a tile's rows are spans of at least
/// 16 pixels, which extrapolate nothing), `None` when a corner's depth is NaN, infinite or 2^64 or more.
fn least_depth(verts: &[ScreenVertex]) -> Option<f32> {
    let (least, _, largest) = depths(verts)?;
    // Beyond 2^64 the fill's slopes could overflow, leaving pixels with no finite depth, never written.
    (largest < 1.8e19).then(|| least - largest * (1.0 / 1024.0))
}

/// The least and greatest of polygon `verts`' corner depths and their largest magnitude; `None` when one
/// is NaN or infinite.
#[inline]
fn depths(verts: &[ScreenVertex]) -> Option<(f32, f32, f32)> {
    let (mut least, mut greatest, mut largest) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
    for v in verts {
        let d = v.attrs[0];
        if !d.is_finite() {
            return None;
        }
        (least, greatest, largest) = (least.min(d), greatest.max(d), largest.max(d.abs()));
    }
    Some((least, greatest, largest))
}

/// A convex polygon's edges as half-planes, in pixels.
struct Convex {
    /// Per edge: a corner `(x, y)`, the edge's direction `(dx, dy)` oriented so that inside is where
    /// `dx * (py - y) - dy * (px - x)` is positive, and the least value that keeps a point a safe distance
    /// inside.
    edges: [(f64, f64, f64, f64, f64); MAX_CORNERS],
    count: usize,
}

/// The most corners [`Convex`] takes (more are never counted as covering).
const MAX_CORNERS: usize = 8;

/// How far inside every edge (in pixels) a tile's rectangle must lie to count as covered: more than the
/// rotated grid's sample shifts (under half a pixel) and any rounding of the fill's edge walk.
const INSIDE: f64 = 1.5;

impl Convex {
    /// The half-planes of `verts` if it is a convex polygon of at most [`MAX_CORNERS`] corners, none
    /// repeated, and a non-zero area.
    fn of(verts: &[ScreenVertex]) -> Option<Self> {
        let n = verts.len();
        if !(3..=MAX_CORNERS).contains(&n) {
            return None;
        }
        let mut corners = [(0i64, 0i64); MAX_CORNERS + 2];
        for (c, v) in corners.iter_mut().zip(verts.iter().chain(verts.iter().take(2))) {
            *c = (i64::from(v.x.0), i64::from(v.y.0));
        }
        // Twice the area and every turn in raw units (exact in i64), to check convexity.
        let (mut area, mut turns_pos, mut turns_neg) = (0i64, false, false);
        for w in corners.get(..n + 2).unwrap_or(&[]).windows(3) {
            let [(ax, ay), (bx, by), (cx, cy)] = [w[0], w[1], w[2]];
            area += ax * by - bx * ay;
            let turn = (bx - ax) * (cy - by) - (by - ay) * (cx - bx);
            turns_pos |= turn > 0;
            turns_neg |= turn < 0;
        }
        // A repeated corner would hide a turn between its neighbours from the check: none is taken.
        let repeated = corners.get(..n + 1).unwrap_or(&[]).windows(2).any(|w| w[0] == w[1]);
        if area == 0 || repeated || (turns_pos && turns_neg) {
            return None;
        }
        let sign = if area > 0 { 1.0 } else { -1.0 };
        let mut edges = [(0.0, 0.0, 0.0, 0.0, 0.0); MAX_CORNERS];
        for (e, w) in edges.iter_mut().zip(corners.get(..n + 1).unwrap_or(&[]).windows(2)) {
            let [(ax, ay), (bx, by)] = [w[0], w[1]];
            let px = |v: i64| v as f64 / 16.0;
            let (dx, dy) = (px(bx - ax) * sign, px(by - ay) * sign);
            *e = (px(ax), px(ay), dx, dy, INSIDE * (dx * dx + dy * dy).sqrt());
        }
        Some(Self { edges, count: n })
    }

    /// The columns `left..right` (pixels) between which a rectangle spanning rows `y` (pixels) lies inside
    /// every edge by [`INSIDE`], if any.
    fn columns(&self, y: (f64, f64)) -> Option<(f64, f64)> {
        let (mut left, mut right) = (f64::NEG_INFINITY, f64::INFINITY);
        for &(ex, ey, dx, dy, least) in self.edges.iter().take(self.count) {
            // The edge's function `dx (py - ey) - dy (px - ex)` is linear; at its least over the rows (the
            // bottom where dx < 0, else the top) it must reach `least` at every column of the rectangle.
            let py = if dx < 0.0 { y.1 } else { y.0 };
            let at = dx * (py - ey) - least;
            let bound = ex + at / dy;
            if dy > 0.0 && bound.is_finite() {
                // Falling with px: the rectangle's right side bounds it, `px <= ex + at / dy`.
                right = right.min(bound);
            } else if dy < 0.0 && bound.is_finite() {
                left = left.max(bound);
            } else if dy != 0.0 || at < 0.0 {
                return None;
            }
        }
        (left < right).then_some((left, right))
    }
}

#[cfg(test)]
#[path = "coarse_depth_tests.rs"]
mod tests;
