//! The anti-aliased fill of a band: each polygon's coverage samples ([`coverage`](super::coverage)) drawn
//! into the band's samples ([`samples`](super::samples)), one shade per pixel per polygon.
//!
//! A pixel row of a polygon splits in two: the pixels whose every sample it covers (the inner run) and the
//! pixels an edge crosses. A polygon with a fast path draws its inner run with the same span loops as the
//! plain fill (SIMD where the CPU has it), then visits the row's expanded pixels there, if the row has any.
//! The crossed pixels, those expanded pixels, and every pixel of a polygon without a fast path are drawn
//! one at a time, each with its own samples, shaded at the pixel's centre from the polygon's attribute
//! planes ([`plane`](super::plane)). Where the colour comes from a texture, the fill first gathers such
//! pixels from all the polygon's rows in the band (up to [`BATCH`]) and shades their texels eight at a
//! time, a lane each, by the inner runs' own vector code ([`span_lanes::colours_at`]); each colour is the
//! one the pixel gets alone, bit for bit, and a pixel drawn once by one polygon does not care when. Every
//! value comes from the polygon and the pixel alone, so a band's pixels do not depend on which thread draws
//! it.

use super::coverage::for_each_row;
use super::plane::Planes;
use super::row::{BandPixels, DROPPED, LANES, SpanCounts, Visibility};
use super::samples::{Pixel, SampleStore};
use super::scanline::Span;
use super::span::{Prepared, Shading, exact_at, shade_surface};
use super::span_lanes::{self, Source, colour_at};
use crate::render::core::options::TextureMode;
use crate::render::core::samples::SamplePattern;
use crate::render::core::vertex::{ScreenVertex, slot};

/// What the band's anti-aliased fill draws into.
pub(crate) struct Target<'p, 'b> {
    /// The band's colour, depth and coverage buffers.
    pub(crate) pixels: &'p mut BandPixels<'b>,
    /// Its expanded pixels.
    pub(crate) store: &'p mut SampleStore,
    /// The sample pattern.
    pub(crate) pattern: &'p SamplePattern,
    /// The band's rows.
    pub(crate) band: (i32, i32),
}

/// Draws one polygon (corners `v`) with its shading into the band's samples, for a pattern of `N` samples
/// (a constant, so that every loop over a pixel's samples unrolls).
///
/// `pending` is the band's list of pixels gathered to be shaded eight at a time, empty between polygons:
/// one list for the band rather than one per polygon, whose 768 bytes were cleared for every polygon.
pub(crate) fn fill_polygon<const N: usize>(
    v: &[ScreenVertex],
    sh: &Shading<'_>,
    prepared: &Prepared<'_>,
    t: &mut Target<'_, '_>,
    pending: &mut Pending,
) -> SpanCounts {
    let Some(planes) = Planes::of(v) else { return SpanCounts::default() };
    let mut dz = [0.0f32; N];
    for (j, d) in dz.iter_mut().enumerate() {
        let (ox, oy) = t.pattern.offset(j);
        *d = planes.dx[slot::DEPTH] * ox + planes.dy[slot::DEPTH] * oy;
    }
    let width = t.pixels.width as i32;
    let fast = prepared.fast().filter(|_| sh.door.is_none());
    let mut total = SpanCounts::default();
    let pattern = *t.pattern;
    let paint = Paint { shading: sh, fast, planes: &planes, dz: &dz };
    // A texel's colour is shaded eight pixels at a time, gathered from any rows (a flat one costs nothing).
    let batched = fast.filter(|(source, _)| !matches!(source, Source::Flat(_)));
    debug_assert_eq!(pending.n, 0, "pixels left from the last polygon");
    for_each_row::<N>(v, &pattern, t.band, width, |cov| {
        let inner = if fast.is_some() && cov.inner.0 < cov.inner.1 { cov.inner } else { (cov.hi, cov.hi) };
        for (x0, x1) in [(cov.lo, inner.0), (inner.1, cov.hi)] {
            for x in x0..x1 {
                pending.visit(batched.is_some(), t, (x, cov.y, cov.mask(x)), &paint, &mut total);
            }
        }
        let Some((source, alpha)) = fast.filter(|_| inner.0 < inner.1) else { return };
        let span = Span { y: cov.y, x0: inner.0, x1: inner.1, a0: planes.at(inner.0, cov.y), da: planes.dx };
        total += span_lanes::draw(&span, source, alpha, sh.visibility, &mut t.pixels.row(cov.y));
        let r = (cov.y - t.band.0) as usize;
        if t.store.row_has_expanded(r) {
            let full = t.pattern.full();
            let start = r * t.pixels.width;
            let mut x = inner.0;
            while let Some(found) = t.store.next_expanded(start + x as usize..start + inner.1 as usize) {
                x = (found - start) as i32;
                pending.visit(batched.is_some(), t, (x, cov.y, full), &paint, &mut total);
                x += 1;
            }
        }
    });
    pending.flush(t, &paint, &mut total);
    total
}

/// The most pixels gathered before they are shaded and drawn.
const BATCH: usize = 8 * LANES;

/// A polygon's pixels waiting to be shaded eight at a time: each one's column, row and samples.
#[derive(Debug)]
pub(crate) struct Pending {
    at: [(i32, i32, u16); BATCH],
    n: usize,
}

impl Pending {
    /// An empty list.
    pub(crate) const EMPTY: Self = Self { at: [(0, 0, 0); BATCH], n: 0 };

    /// Draws samples `mask` of pixel `(x, y)` now, or when `batched` gathers it to be shaded with others
    /// (shading and drawing the list when it is full).
    #[inline]
    fn visit<const N: usize>(
        &mut self,
        batched: bool,
        t: &mut Target<'_, '_>,
        (x, y, mask): (i32, i32, u16),
        paint: &Paint<'_, N>,
        total: &mut SpanCounts,
    ) {
        if !batched || mask == 0 {
            return pixel(t, paint, x, y, mask, SHADE_HERE, total);
        }
        if let Some(slot) = self.at.get_mut(self.n) {
            *slot = (x, y, mask);
            self.n += 1;
        }
        if self.n >= BATCH {
            self.flush(t, paint, total);
        }
    }

    /// Shades the pixels gathered, eight at a time ([`span_lanes::colours_at`]), draws them and empties the
    /// list. Each pixel is drawn once and by one polygon here, so drawing them after the polygon's inner
    /// runs of later rows changes nothing.
    fn flush<const N: usize>(&mut self, t: &mut Target<'_, '_>, paint: &Paint<'_, N>, total: &mut SpanCounts) {
        let Some((source, alpha)) = paint.fast else {
            // Only a polygon with a fast path gathers pixels; any others are drawn shaded there.
            debug_assert_eq!(self.n, 0, "pixels gathered for a polygon without a fast path");
            for &(x, y, mask) in &self.at[..self.n] {
                pixel(t, paint, x, y, mask, SHADE_HERE, total);
            }
            self.n = 0;
            return;
        };
        for chunk in self.at[..self.n].chunks(LANES) {
            let mut a = [[0.0f32; 4]; LANES];
            for (l, &(x, y, _)) in chunk.iter().enumerate() {
                let p = paint.planes.at(x, y);
                a[l] = [p[0], p[1], p[2], p[3]];
            }
            // Lanes past the last pixel repeat the first (valid values, and the same mip level).
            for l in chunk.len()..LANES {
                a[l] = a[0];
            }
            let colours = span_lanes::colours_at(source, alpha, &a);
            for (&(x, y, mask), &c) in chunk.iter().zip(&colours) {
                pixel(t, paint, x, y, mask, c, total);
            }
        }
        self.n = 0;
    }
}

/// How one polygon's pixels are shaded and where its `N` samples' depths lie.
struct Paint<'a, const N: usize> {
    shading: &'a Shading<'a>,
    /// The fast path's source and alpha mask, if the polygon has one.
    fast: Option<(Source<'a>, Option<(f32, f32)>)>,
    planes: &'a Planes,
    /// Each sample's depth less the pixel centre's.
    dz: &'a [f32; N],
}

/// [`pixel`]'s `pre` when the pixel is to be shaded there, at its centre (a colour is `0x00RRGGBB`, so
/// never this, nor [`DROPPED`]).
const SHADE_HERE: u32 = u32::MAX - 1;

/// Draws samples `mask` of pixel `x` of row `y`, shading it at its centre, or taking `pre`, its colour
/// shaded with others ([`DROPPED`] where the alpha mask dropped it; [`SHADE_HERE`] for neither), and adds
/// what it did to `total`. Every argument is a scalar or a pointer: a tuple would be passed through memory,
/// written a field at a time and read back a word at a time, which stalls store forwarding on every call
/// (as a returned record would, hence `total` by reference).
#[inline]
fn pixel<const N: usize>(
    t: &mut Target<'_, '_>,
    paint: &Paint<'_, N>,
    x: i32,
    y: i32,
    mask: u16,
    pre: u32,
    total: &mut SpanCounts,
) {
    let Paint { shading: sh, fast, planes, dz } = *paint;
    if mask == 0 || sh.door.hides(x, y) {
        return;
    }
    let a = planes.at(x, y);
    let centre = a[slot::DEPTH];
    let px = &mut *t.pixels;
    let r = (y as usize).wrapping_sub(px.y0);
    let index = r * px.width + x as usize;
    let words = px.words;
    let Some(color) = px.color.get_mut(index) else { return };
    let pixel = Pixel {
        index,
        row: r,
        color,
        depth: if sh.visibility == Visibility::DepthTest { px.depth.get_mut(index) } else { None },
        covered: if sh.visibility == Visibility::Coverage {
            px.coverage.get_mut(r * words + (x as usize >> 6)).map(|w| (w, 1u64 << (x & 63)))
        } else {
            None
        },
    };
    let perspective = sh.mode != TextureMode::Affine;
    *total += t.store.draw(pixel, mask, sh.visibility, (centre, dz), || match (pre, fast) {
        (DROPPED, _) => None,
        (SHADE_HERE, Some((source, alpha))) => colour_at(source, alpha, [a[0], a[1], a[2], a[3]]),
        (colour, _) if colour != SHADE_HERE => Some(colour),
        _ => {
            let footprint = sh.footprint_at([a[slot::Q], a[slot::S], a[slot::T]]);
            shade_surface(sh, &exact_at(&a, &planes.dx, 0.0, perspective), &footprint)
        }
    });
}

/// Resolves the band's expanded pixels (of `N` samples) into its colours.
pub(crate) fn resolve<const N: usize>(t: &mut Target<'_, '_>, vis: Visibility) {
    let rows = (t.band.1 - t.band.0).max(0) as usize;
    for r in 0..rows {
        t.store.resolve_row::<N>(r, t.pixels.width, t.pixels.color, vis);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::mip::TexGradients;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::texture::{Filter, Sampler, Texture};
    use crate::render::fill::span_lanes::colours_at;
    use crate::render::fill::texel::Tex;

    #[test]
    fn pixels_shaded_eight_at_a_time_are_the_pixels_shaded_alone() {
        let mut rng = Lcg(21);
        let texels = (0..64 * 32).map(|_| rng.next() & 0x00ff_ffff | rng.below(256) << 24).collect();
        let Ok(chain) = Texture::new(64, 32, texels) else { panic!("texture") };
        let g = TexGradients { dx: [0.001, 0.02, -0.01], dy: [0.0, 0.01, 0.03] };
        let hostile = [f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0, -0.0, 1e-30, -1e30, 3e9];
        // On a CPU with AVX2 the vector path is the one under test.
        assert_eq!(crate::render::simd::avx2().is_some(), crate::render::simd::has_avx2());
        let mut kept = 0;
        for case in 0..3000 {
            let filters = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear, Filter::Anisotropic(4), Filter::Area];
            let filter = filters[(case / 5) % 5];
            let tex = match case % 4 {
                _ if filter == Filter::Area => Tex::per_pixel(&chain, Sampler::default(), filter, g),
                0 | 1 => Tex::per_pixel(&chain, Sampler::default(), filter, g),
                _ => Tex::polygon(&chain, Sampler::default(), filter, (case % 7) as f32 * 0.4),
            };
            let source = if case % 5 < 3 { Source::Texel(tex) } else { Source::Tinted(tex, [40_000, 65_536, 9_000]) };
            // Every other case an alpha mask that drops some of the (filtered: averaged) texels.
            let alpha = ((case / 3) % 2 == 0).then_some((1.0, 0.45));
            let mut a = [[0.0f32; 4]; LANES];
            let unit = |rng: &mut Lcg| (rng.below(20_001) as f32 - 10_000.0) / 10_000.0;
            // Half the cases: pixels near one another, as a polygon's edge pixels are (so their levels are
            // mostly shared, and the vector fetch from one level is taken); half: unrelated pixels.
            let near = case % 2 == 0;
            let base = [unit(&mut rng), 0.05 + unit(&mut rng).abs() * 2.0, unit(&mut rng) * 3.0, unit(&mut rng) * 3.0];
            for lane in &mut a {
                *lane = if near {
                    base.map(|b| b + unit(&mut rng) * 1e-3 * b.abs().max(1.0))
                } else {
                    [unit(&mut rng), 0.05 + unit(&mut rng).abs() * 2.0, unit(&mut rng) * 3.0, unit(&mut rng) * 3.0]
                };
                // Now and then a value no frame should hold.
                if rng.below(if near { 40 } else { 10 }) == 0 {
                    lane[1 + rng.below(3) as usize] = hostile[rng.below(8) as usize];
                }
            }
            let together = colours_at(source, alpha, &a);
            kept += together.iter().filter(|&&c| c != DROPPED).count();
            for (l, lane) in a.iter().enumerate() {
                let alone = colour_at(source, alpha, *lane);
                assert_eq!((together[l] != DROPPED).then_some(together[l]), alone, "case {case}, lane {l}: {lane:?}");
            }
        }
        assert!(kept > 3000 * LANES * 3 / 5, "only {kept} pixels kept");
    }
}
