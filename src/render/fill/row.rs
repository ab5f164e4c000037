//! What the pixel loops draw into and count, and the records they share: a band's row of colour, depth and
//! coverage, a run of pixels with its attributes, and the coverage bits.

use super::scanline::Span;
use crate::render::core::texture::floor_i32;
use crate::render::core::vertex::{ATTRS, ScreenVertex, slot};

/// How a pixel decides whether it may be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// Always write (painter's order: later polygons cover earlier ones).
    Overwrite,
    /// Write when nearer than the depth buffer, then store the depth (`zbuffer`).
    DepthTest,
    /// Write only where nothing was drawn yet, then mark the pixel (`bucket-near`, front to back).
    Coverage,
}

/// The buffers of one frame row.
pub struct Row<'a> {
    /// Colour, `0x00RRGGBB`, one per pixel.
    pub color: &'a mut [u32],
    /// Depth (larger is nearer), one per pixel; may be empty unless [`Visibility::DepthTest`].
    pub depth: &'a mut [f32],
    /// 'Already drawn' bits, 64 pixels a word; may be empty unless [`Visibility::Coverage`].
    pub coverage: &'a mut [u64],
}

/// A band's colour, depth and coverage buffers as one slice each, rows `y0..` of a frame `width` pixels
/// wide: what a band's fill draws into, a row at a time ([`BandPixels::row`]) or, for narrow small
/// triangles, four columns at a time.
pub(crate) struct BandPixels<'a> {
    /// First frame row of the band.
    pub(crate) y0: usize,
    /// Frame width in pixels.
    pub(crate) width: usize,
    /// Colour, `width` pixels a row.
    pub(crate) color: &'a mut [u32],
    /// Depths (larger is nearer), empty unless the band is depth tested.
    pub(crate) depth: &'a mut [f32],
    /// 'Already drawn' bits, `words` words a row, empty unless the band draws each pixel once.
    pub(crate) coverage: &'a mut [u64],
    /// Coverage words a row.
    pub(crate) words: usize,
}

impl BandPixels<'_> {
    /// The same buffers, borrowed for a shorter time.
    #[inline(always)]
    pub(crate) fn reborrow(&mut self) -> BandPixels<'_> {
        BandPixels {
            y0: self.y0,
            width: self.width,
            color: &mut *self.color,
            depth: &mut *self.depth,
            coverage: &mut *self.coverage,
            words: self.words,
        }
    }

    /// The buffers of frame row `y` (which must be in the band).
    #[inline(always)]
    pub(crate) fn row(&mut self, y: i32) -> Row<'_> {
        let (r, w, words) = (y as usize - self.y0, self.width, self.words);
        Row {
            color: &mut self.color[r * w..(r + 1) * w],
            depth: if self.depth.is_empty() { &mut [] } else { &mut self.depth[r * w..(r + 1) * w] },
            coverage: if self.coverage.is_empty() { &mut [] } else { &mut self.coverage[r * words..(r + 1) * words] },
        }
    }

    /// The pixels of the four columns from `x_start` that `m` covers on band row `row` and that are not yet
    /// drawn, which are marked drawn now ([`COVERAGE`]: each pixel drawn once); pixels whose coverage word
    /// is missing count as drawn, as in the per-pixel loop.
    #[inline(always)]
    pub(crate) fn claim(&mut self, row: usize, x_start: usize, m: u32) -> u32 {
        let words = self.coverage.get_mut(row * self.words..(row + 1) * self.words).unwrap_or(&mut []);
        let pass = m & !u32::from(coverage_byte(words, x_start));
        cover_bits(words, x_start, pass as u8);
        pass
    }
}

/// Pixel counts from drawing spans.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpanCounts {
    /// Pixels whose colour was computed (texture fetch and colour multiply).
    pub shaded: u64,
    /// Pixels written to the frame.
    pub written: u64,
    /// Pixels skipped by the visibility test before shading.
    pub rejected: u64,
}

/// A span's pixel counts in one word, 21 bits each (a span is at most a row, and the renderer refuses
/// frames of more than 2^20 pixels a side): shaded, written, rejected from the low bits up.
///
/// The chunk loop returns them so, in a register, and takes the texture by reference: a copy made for
/// every span, and counts written a field at a time and read back as one vector, each cost a failed
/// store-to-load forward a span (together 2-4% of a mountain frame, whose spans are short).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PackedCounts(u64);

impl PackedCounts {
    /// Bits for each count.
    pub(crate) const BITS: u32 = 21;
    const MASK: u64 = (1 << Self::BITS) - 1;

    /// Adds `shaded`, `written` and `rejected` pixels (each total stays below 2^21).
    #[inline(always)]
    pub(crate) fn add(&mut self, shaded: u64, written: u64, rejected: u64) {
        self.0 += shaded | written << Self::BITS | rejected << (2 * Self::BITS);
    }

    /// The counts unpacked.
    #[inline(always)]
    pub(crate) fn unpack(self) -> SpanCounts {
        SpanCounts {
            shaded: self.0 & Self::MASK,
            written: self.0 >> Self::BITS & Self::MASK,
            rejected: self.0 >> (2 * Self::BITS) & Self::MASK,
        }
    }
}

impl std::ops::Add for SpanCounts {
    type Output = Self;

    /// The counts of two sets of spans together.
    fn add(self, o: Self) -> Self {
        Self { shaded: self.shaded + o.shaded, written: self.written + o.written, rejected: self.rejected + o.rejected }
    }
}

impl std::ops::AddAssign for SpanCounts {
    /// Adds another set of spans' counts.
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

/// Pixels per chunk: eight `f32` fill one AVX register or two SSE registers.
pub const LANES: usize = 8;

/// Pixels `x0..x1` of one row, with depth, `1/w`, `s/w` and `t/w` at the centre of `x0` and their change
/// per pixel.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Run {
    /// First pixel.
    pub(crate) x0: usize,
    /// First pixel drawn (at least `x0`: the pixels before it are known to fail the depth test), where the
    /// attributes are still those of the pixels from `x0`.
    pub(crate) from: usize,
    /// End pixel (exclusive).
    pub(crate) x1: usize,
    /// Depth, `1/w`, `s/w`, `t/w` at the centre of `x0`.
    pub(crate) a0: [f32; 4],
    /// Their change per pixel.
    pub(crate) da: [f32; 4],
    /// The caller has found the texel coordinates of every pixel in range for the whole polygon
    /// ([`corners_in_range`]), so the chunk loop need not check this run ([`Setup::texels_in_range`]).
    pub(crate) in_range: bool,
}

/// True when the texel coordinates of every pixel a polygon with these corners covers are finite and
/// within `±2^22` as the span loops compute them ([`Setup::texels_in_range`]'s promise, made once for
/// all of the polygon's spans instead of by two divisions a span), from the corners' x and their `1/w`,
/// `s/w` and `t/w`; `(w, h)` is the texture's size.
///
/// Why it holds: inside a convex polygon with `1/w` positive at every corner, `1/w` is a convex
/// combination of the corners' values, and `u = (s/w) / (1/w)` (a ratio of linear functions with a positive
/// denominator) takes its extremes at corners; so every pixel's exact `1/w` is at least the smallest
/// corner's, and its `u`, `v` lie within the corners'. The spans' values stray from the exact ones mostly
/// where a span is a sliver: the walk places each edge at a row by a float product (the edge's x at its
/// top plus its slope times the rows down), which with every corner within 4096 pixels of x = 0 is off by
/// at most about `2^-24 * 20480`, 0.0012 of a pixel, while the covered pixels come from the exact integer
/// rule; so a pixel centre may lie that far outside the float edges, and across a span as narrow as 1/64 of
/// a pixel (narrower ones take the left edge's values) an attribute is extrapolated by up to 8% of its
/// change across the span. Requiring the smallest `1/w` to be at least an eighth of the largest keeps `1/w`
/// above 44% of the smallest corner's, so `u`, `v` grow at most about 2.7-fold, and the corners' texel
/// coordinates within `±2^20` leave that factor within `2^22`. A polygon that fails (NaN, a corner near the
/// eye plane or far to the side, a coordinate far out) is checked a span at a time. (A corner 8,000 pixels
/// out, in the clipper's guard band, with a sixteen-fold `1/w` was seen to break a looser rule.)
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) fn corners_in_range(corners: &[ScreenVertex], (w, h): (f32, f32)) -> bool {
    const LIMIT: f32 = 1_048_576.0;
    /// 4096 pixels in `Fx28_4` units.
    const X_LIMIT: i32 = 4096 * 16;
    let (mut q_min, mut q_max) = (f32::INFINITY, 0.0f32);
    for v in corners {
        let (x_raw, q, s, t) = (v.x.0, v.attrs[slot::Q], v.attrs[slot::S], v.attrs[slot::T]);
        let (x, y) = (s / q * w, t / q * h);
        // Written so that NaN fails every test.
        if !(x_raw.unsigned_abs() < X_LIMIT as u32
            && q > 1e-20
            && q < f32::INFINITY
            && x.abs() < LIMIT
            && y.abs() < LIMIT)
        {
            return false;
        }
        (q_min, q_max) = (q_min.min(q), q_max.max(q));
    }
    q_max > 0.0 && q_min >= q_max * (1.0 / 8.0)
}

/// One row's span for the chunk loop across rows (`span_avx2::rows`): pixels `x0..x1` of frame row `y`,
/// its set-up, and whether its texel coordinates stay in range ([`Setup::texels_in_range`]).
#[derive(Clone, Copy)]
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
pub(crate) struct RowRun {
    pub(crate) y: usize,
    pub(crate) x0: usize,
    pub(crate) x1: usize,
    pub(crate) in_range: bool,
    pub(crate) setup: Setup,
}

/// [`Visibility`] as a constant for the pixel loops' `VIS` parameter: [`Visibility::Overwrite`].
pub(crate) const OVERWRITE: u8 = 0;
/// [`Visibility::DepthTest`].
pub(crate) const DEPTH_TEST: u8 = 1;
/// [`Visibility::Coverage`].
pub(crate) const COVERAGE: u8 = 2;
/// The pixel loops' colour source, their `SRC` parameter: one flat colour.
pub(crate) const FLAT: u8 = 0;
/// The nearest texel as is.
pub(crate) const TEXEL: u8 = 1;
/// The nearest texel times the polygon's colour.
pub(crate) const TINTED: u8 = 2;

/// Marks a pixel whose colour was not given, the alpha mask having dropped it (a colour is `0x00RRGGBB`,
/// so never this).
pub(crate) const DROPPED: u32 = u32::MAX;

/// Attribute values of one span, hoisted out of the loops.
#[derive(Clone, Copy)]
pub(crate) struct Setup {
    pub(crate) d0: f32,
    pub(crate) dd: f32,
    pub(crate) q0: f32,
    pub(crate) dq: f32,
    pub(crate) s0: f32,
    pub(crate) ds: f32,
    pub(crate) t0: f32,
    pub(crate) dt: f32,
    pub(crate) w: f32,
    pub(crate) h: f32,
}

impl Setup {
    /// The set-up of a run whose depth, `1/w`, `s/w` and `t/w` are `a0` at its first pixel and change by
    /// `da` a pixel, for a texture of `size` texels (`(0, 0)` for none).
    #[inline(always)]
    pub(crate) fn new(a0: [f32; 4], da: [f32; 4], (w, h): (f32, f32)) -> Self {
        Self { d0: a0[0], dd: da[0], q0: a0[1], dq: da[1], s0: a0[2], ds: da[2], t0: a0[3], dt: da[3], w, h }
    }

    /// The set-up of a span from the walk (its attributes at its first pixel, `x0`), for a texture of `size`.
    #[inline(always)]
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(crate) fn of_span(span: &Span, size: (f32, f32)) -> Self {
        let pick = |a: &[f32; ATTRS]| [a[slot::DEPTH], a[slot::Q], a[slot::S], a[slot::T]];
        Self::new(pick(&span.a0), pick(&span.da), size)
    }

    /// The depth at pixel offset `k` from the span's start.
    #[inline(always)]
    pub(crate) fn depth(&self, k: f32) -> f32 {
        self.d0 + k * self.dd
    }

    /// The texture coordinates `(u, v)` at pixel offset `k` (perspective-correct).
    #[inline(always)]
    pub(crate) fn uv(&self, k: f32) -> (f32, f32) {
        let q = 1.0 / (self.q0 + k * self.dq);
        ((self.s0 + k * self.ds) * q, (self.t0 + k * self.dt) * q)
    }

    /// True when the texel coordinates of every pixel of a span `0..=last` (in offsets from its start) are
    /// finite and within `±2^22`. Perspective-correct coordinates are ratios of linear functions, monotone
    /// wherever the denominator `1/w` keeps its sign, so checking both ends (with `1/w` clearly positive at
    /// both) bounds the pixels between them. The bound leaves the bilinear rule's positions in 1/256 texel
    /// within `±2^30`, and the margin to `2^31` covers the rounding of every product.
    pub(crate) fn texels_in_range(&self, last: usize) -> bool {
        let s = self;
        let at = |k: f32| {
            let q = s.q0 + k * s.dq;
            let r = 1.0 / q;
            let (x, y) = ((s.s0 + k * s.ds) * r * s.w, (s.t0 + k * s.dt) * r * s.h);
            q > 1e-30 && q.is_finite() && x.abs() < 4_194_304.0 && y.abs() < 4_194_304.0
        };
        at(0.0) && at(last as f32)
    }

    /// The texel coordinates at pixel offset `k` (perspective-correct), floored.
    #[inline(always)]
    pub(crate) fn texel_xy(&self, k: f32) -> (i32, i32) {
        let q = 1.0 / (self.q0 + k * self.dq);
        let u = (self.s0 + k * self.ds) * q;
        let v = (self.t0 + k * self.dt) * q;
        (floor_i32(u * self.w), floor_i32(v * self.h))
    }
}

/// The 'already drawn' bits of pixels `x..x + 8`, bit `i` for pixel `x + i` (missing words read as drawn).
#[inline(always)]
pub(crate) fn coverage_byte(coverage: &[u64], x: usize) -> u8 {
    let (word, shift) = (x >> 6, (x & 63) as u32);
    let lo = coverage.get(word).copied().unwrap_or(u64::MAX) >> shift;
    let hi = if shift > 56 { coverage.get(word + 1).copied().unwrap_or(u64::MAX) << (64 - shift) } else { 0 };
    (lo | hi) as u8
}

/// Marks pixel `x + i` as drawn for every bit `i` set in `bits`.
#[inline(always)]
pub(crate) fn cover_bits(coverage: &mut [u64], x: usize, bits: u8) {
    let (word, shift) = (x >> 6, (x & 63) as u32);
    if let Some(w) = coverage.get_mut(word) {
        *w |= u64::from(bits) << shift;
    }
    if shift > 56
        && let Some(w) = coverage.get_mut(word + 1)
    {
        *w |= u64::from(bits) >> (64 - shift);
    }
}
