//! The anti-aliased fill of a band: each polygon's coverage samples ([`coverage`](super::coverage)) drawn
//! into the band's samples ([`samples`](super::samples)), one shade per pixel per polygon.
//!
//! A pixel row of a polygon splits in two: the pixels whose every sample it covers (the inner run) and the
//! pixels an edge crosses. A polygon with a fast path draws its inner run with the same span loops as the
//! plain fill (SIMD where the CPU has it), then visits the row's expanded pixels there, if the row has any;
//! the crossed pixels, and every pixel of a polygon without a fast path, go one at a time, shaded at the
//! pixel's centre from the polygon's attribute planes ([`plane`](super::plane)). Every value comes from the
//! polygon and the row alone, so a band's pixels do not depend on which thread draws it.

use super::coverage::{RowCoverage, for_each_row};
use super::plane::Planes;
use super::row::{BandPixels, SpanCounts, Visibility};
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
    for_each_row::<N>(v, &pattern, t.band, width, |cov| {
        let inner = if fast.is_some() && cov.inner.0 < cov.inner.1 { cov.inner } else { (cov.hi, cov.hi) };
        for x in (cov.lo..inner.0).chain(inner.1..cov.hi) {
            pixel(t, cov, (x, cov.mask(x)), &paint, &mut total);
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
                pixel(t, cov, (x, full), &paint, &mut total);
                x += 1;
            }
        }
    });
    total
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

/// Draws samples `mask` of pixel `x` of the row `cov` describes, shading it at its centre, and adds what
/// it did to `total` (by reference: a returned record comes back through memory, where the caller's wide
/// read of the callee's narrow writes stalls store forwarding).
#[inline]
fn pixel<const N: usize>(
    t: &mut Target<'_, '_>,
    cov: &RowCoverage<N>,
    (x, mask): (i32, u16),
    paint: &Paint<'_, N>,
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
    *total += t.store.draw(pixel, mask, sh.visibility, (centre, dz), || match fast {
        Some((source, alpha)) => colour_at(source, alpha, [a[0], a[1], a[2], a[3]]),
        None => {
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
