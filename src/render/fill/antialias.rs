//! The anti-aliased fill of a band: each polygon's coverage samples ([`coverage`](super::coverage)) drawn
//! into the band's samples ([`samples`](super::samples)), one shade per pixel per polygon.
//!
//! A pixel row of a polygon splits in two: the pixels whose every sample it covers (the inner run) and the
//! pixels an edge crosses. A polygon with a fast path draws its inner run with the same span loops as the
//! plain fill (SIMD where the CPU has it), then visits the row's expanded pixels there, if the row has any;
//! the crossed pixels, and every pixel of a polygon without a fast path, go one at a time, shaded at the
//! pixel's centre from the polygon's attribute planes ([`plane`](super::plane)); where the fast path's
//! colour is costly (a filter, or a level per pixel), a run of crossed pixels is shaded ahead by the fast
//! loops instead, eight lanes at a time, stepping from the run's first pixel. Every value comes from the
//! polygon and the row alone, so a band's pixels do not depend on which thread draws it.

use super::coverage::{RowCoverage, for_each_row};
use super::plane::Planes;
use super::row::{BandPixels, LANES, Row, SpanCounts, Visibility};
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
pub(crate) fn fill_polygon<const N: usize>(
    v: &[ScreenVertex],
    sh: &Shading<'_>,
    prepared: &Prepared<'_>,
    t: &mut Target<'_, '_>,
) -> SpanCounts {
    let Some(planes) = Planes::of(v) else { return SpanCounts::default() };
    let mut dz = [0.0f32; N];
    for (j, d) in dz.iter_mut().enumerate() {
        let (ox, oy) = t.pattern.offset(j);
        *d = planes.dx[slot::DEPTH] * ox + planes.dy[slot::DEPTH] * oy;
    }
    let width = t.pixels.width as i32;
    let fast = prepared.fast().filter(|_| !sh.screen_door);
    let mut total = SpanCounts::default();
    let pattern = *t.pattern;
    let paint = Paint { shading: sh, fast, planes: &planes, dz: &dz };
    // A costly colour is shaded for a run of crossed pixels at once, eight lanes at a time.
    let ahead = fast.filter(|(source, _)| source.costly());
    let mut colours = [UNSHADED; AHEAD];
    for_each_row::<N>(v, &pattern, t.band, width, |cov| {
        let inner = if fast.is_some() && cov.inner.0 < cov.inner.1 { cov.inner } else { (cov.hi, cov.hi) };
        for (x0, x1) in [(cov.lo, inner.0), (inner.1, cov.hi)] {
            let shaded = ahead.is_some_and(|(s, alpha)| shade_ahead(s, alpha, &planes, (cov.y, x0, x1), &mut colours));
            for x in x0..x1 {
                let pre = colours.get((x - x0) as usize).filter(|_| shaded).map(|&c| (c != UNSHADED).then_some(c));
                pixel(t, cov, (x, cov.mask(x)), (&paint, pre), &mut total);
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
                pixel(t, cov, (x, full), (&paint, None), &mut total);
                x += 1;
            }
        }
    });
    total
}

/// The longest run of crossed pixels shaded ahead (longer runs, from edges close to horizontal, are shaded
/// a pixel at a time as they are visited).
const AHEAD: usize = 64;

/// Marks a pixel shaded ahead that the alpha mask drops (a colour is `0x00RRGGBB`, so never this).
const UNSHADED: u32 = u32::MAX;

/// Shades pixels `x0..x1` of row `y` into `out` (from its start) with the fast loops, stepping the
/// attributes from `x0` as an inner run does, and marks those the alpha mask drops [`UNSHADED`]; false (and
/// nothing shaded) when the run is empty or longer than `out`. Only the run's chunks of `out` are written.
fn shade_ahead(
    source: Source<'_>,
    alpha: Option<(f32, f32)>,
    planes: &Planes,
    (y, x0, x1): (i32, i32, i32),
    out: &mut [u32; AHEAD],
) -> bool {
    let n = (x1 - x0).max(0) as usize;
    // A chunk's worth of row at least, so the chunk loop takes even a short run.
    let Some(row) = out.get_mut(..n.next_multiple_of(LANES).max(LANES)) else { return false };
    if n == 0 {
        return false;
    }
    row.fill(UNSHADED);
    let span = Span { y, x0: 0, x1: n as i32, a0: planes.at(x0, y), da: planes.dx };
    span_lanes::draw(
        &span,
        source,
        alpha,
        Visibility::Overwrite,
        &mut Row { color: row, depth: &mut [], coverage: &mut [] },
    );
    true
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

/// Draws samples `mask` of pixel `x` of the row `cov` describes, shading it at its centre (or taking `pre`,
/// its colour shaded ahead, `Some(None)` where the alpha mask dropped it), and adds what
/// it did to `total` (by reference: a returned record comes back through memory, where the caller's wide
/// read of the callee's narrow writes stalls store forwarding).
#[inline]
fn pixel<const N: usize>(
    t: &mut Target<'_, '_>,
    cov: &RowCoverage<N>,
    (x, mask): (i32, u16),
    (paint, pre): (&Paint<'_, N>, Option<Option<u32>>),
    total: &mut SpanCounts,
) {
    let Paint { shading: sh, fast, planes, dz } = *paint;
    if mask == 0 || sh.screen_door && (x + cov.y) & 1 != 0 {
        return;
    }
    let a = planes.at(x, cov.y);
    let centre = a[slot::DEPTH];
    let px = &mut *t.pixels;
    let r = (cov.y as usize).wrapping_sub(px.y0);
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
        (Some(colour), _) => colour,
        (None, Some((source, alpha))) => colour_at(source, alpha, [a[0], a[1], a[2], a[3]]),
        (None, None) => {
            let lod = sh.lod_at([a[slot::Q], a[slot::S], a[slot::T]]);
            shade_surface(sh, &exact_at(&a, &planes.dx, 0.0, perspective), lod)
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
    use crate::render::core::vertex::ATTRS;
    use crate::render::fill::texel::Tex;
    use crate::render::simd::force_portable;

    #[test]
    fn crossed_pixels_shaded_ahead_are_the_pixels_shaded_alone() {
        let mut rng = Lcg(21);
        let texels = (0..64 * 32).map(|_| rng.next()).collect();
        let Ok(chain) = Texture::new(64, 32, texels) else { panic!("texture") };
        let g = TexGradients { dx: [0.001, 0.02, -0.01], dy: [0.0, 0.01, 0.03] };
        // Attributes and steps in 1/64ths, so stepping along a run and evaluating the plane at each pixel give
        // the same values exactly, and so the same colours.
        let dyadic = |rng: &mut Lcg, scale: f32| (rng.below(129) as f32 - 64.0) / 64.0 * scale;
        for case in 0..600 {
            let mut a0 = [0.0; ATTRS];
            let (mut dx, mut dy) = ([0.0; ATTRS], [0.0; ATTRS]);
            a0[slot::Q] = 1.0 + dyadic(&mut rng, 0.5);
            for k in [slot::S, slot::T] {
                (a0[k], dx[k], dy[k]) = (dyadic(&mut rng, 4.0), dyadic(&mut rng, 0.25), dyadic(&mut rng, 0.25));
            }
            let planes = Planes::new((0.5, 0.5), a0, dx, dy);
            let filter = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][case % 3];
            let tex = if case % 2 == 0 {
                Tex::per_pixel(&chain, Sampler::default(), filter, g)
            } else {
                Tex::polygon(&chain, Sampler::default(), filter, 1.25)
            };
            let source = if case % 4 < 2 { Source::Texel(tex) } else { Source::Tinted(tex, [40_000, 65_536, 9_000]) };
            // An alpha mask that drops about half the texels.
            let alpha = (case % 5 != 0).then_some((1.0, 0.5));
            let (y, x0) = (rng.below(40) as i32, rng.below(40) as i32);
            let n = 1 + (case % 70) as i32;
            for portable in [false, true] {
                force_portable(portable);
                let mut out = [0u32; AHEAD];
                let shaded = shade_ahead(source, alpha, &planes, (y, x0, x0 + n), &mut out);
                force_portable(false);
                assert_eq!(shaded, n as usize <= AHEAD, "case {case}: a run of {n}");
                if !shaded {
                    continue;
                }
                for i in 0..n {
                    let a = planes.at(x0 + i, y);
                    let alone = colour_at(source, alpha, [a[0], a[1], a[2], a[3]]);
                    let ahead = out[i as usize];
                    assert_eq!((ahead != UNSHADED).then_some(ahead), alone, "case {case}, pixel {i} of {n}");
                }
            }
        }
    }
}
