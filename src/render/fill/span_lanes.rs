//! The span fast paths: flat colour, texel, and tinted texel (from the polygon's mip level, or from the
//! level chosen at each pixel), under every visibility rule, one monomorphised pixel loop for each
//! combination.
//!
//! [`walk`] draws a run of pixels: where the CPU has AVX2 the run's whole chunks of [`LANES`] pixels (and
//! a short run whole, when its texel is costly: filtered, or a level per pixel) go through the vector loop
//! (`span_avx2`), and the rest (or, without AVX2, all of it) through the per-pixel loop here, which is the reference the vector loop matches bit for bit: the same IEEE operations in the
//! same order, no fused multiply-add; a level chosen per pixel is measured there the same way (the
//! `log2_approx` quartic on eight lanes). Writes are selects (the old value where the visibility test
//! failed), so a rejected pixel keeps its colour and depth bit for bit. [`dispatch`] picks the loop for a
//! polygon's source and visibility once, so a group of polygons shares it.

use super::row::{
    COVERAGE, DEPTH_TEST, DROPPED, FLAT, LANES, OVERWRITE, Row, Run, Setup, SpanCounts, TEXEL, TINTED, Visibility,
};
use super::scanline::Span;
use super::texel::Tex;
use crate::render::core::vertex::slot;
#[cfg(target_arch = "x86_64")]
use crate::render::simd;

/// Where a fast-path pixel's colour comes from.
#[derive(Clone, Copy)]
pub(crate) enum Source<'a> {
    /// One packed colour for the whole span.
    Flat(u32),
    /// The texel (nearest or filtered, see [`Tex`]), perspective-correct, used as is.
    Texel(Tex<'a>),
    /// The texel times the polygon's one colour, in `Fx16` (65536 is 1.0) per channel; the product
    /// is rounded to the nearest 1/255 in integers, which equals the general path's float rounding except
    /// within 1/500 of a level's boundary, where it may be one level off.
    Tinted(Tex<'a>, [u32; 3]),
}

impl<'a> Source<'a> {
    /// The same source with a chain's texture (a per-pixel [`Tex`]) filtered at level of detail `lod`
    /// for every pixel (the level of a span, chosen at its middle).
    #[inline]
    pub(crate) fn at_lod(self, lod: f32) -> Self {
        let fixed = |t: Tex<'a>| Tex::polygon(t.texture, t.sampler, t.filter, lod);
        match self {
            Source::Flat(c) => Source::Flat(c),
            Source::Texel(t) => Source::Texel(fixed(t)),
            Source::Tinted(t, tint) => Source::Tinted(fixed(t), tint),
        }
    }
}

/// Draws a span with a fast-path source under a visibility rule.
pub(crate) fn draw(
    span: &Span,
    source: Source<'_>,
    alpha: Option<(f32, f32)>,
    vis: Visibility,
    row: &mut Row<'_>,
) -> SpanCounts {
    struct OneSpan<'s, 'r, 'b>(&'s Span, &'r mut Row<'b>);
    impl Fill for OneSpan<'_, '_, '_> {
        #[inline(always)]
        fn fill<const VIS: u8, const SRC: u8>(self, paint: &Paint<'_>) -> SpanCounts {
            span_run::<VIS, SRC>(self.0, paint, self.1, false, (0, usize::MAX))
        }
    }
    dispatch(source, alpha, vis, OneSpan(span, row))
}

/// Draws a span with the loop for visibility `VIS` and source `SRC` (as [`dispatch`] chose them): what
/// [`draw`] does once the loop is chosen, for a caller drawing many spans with one choice. Only the span's
/// pixels in columns `from..to` are drawn (`(0, usize::MAX)` for all), those outside known to fail the
/// depth test; the pixels drawn get the attributes they get in the whole span.
#[inline(always)]
pub(crate) fn span_run<const VIS: u8, const SRC: u8>(
    span: &Span,
    paint: &Paint<'_>,
    row: &mut Row<'_>,
    in_range: bool,
    (from, to): (usize, usize),
) -> SpanCounts {
    // One colour over everything: a plain fill (a memset) beats any per-pixel loop.
    if SRC == FLAT && VIS == OVERWRITE {
        let n = span.x1.saturating_sub(span.x0).max(0) as u64;
        return match row.color.get_mut(span.x0.max(0) as usize..span.x1.max(0) as usize) {
            Some(run) => {
                run.fill(paint.flat());
                SpanCounts { shaded: n, written: n, rejected: 0 }
            }
            None => SpanCounts::default(),
        };
    }
    let (a0, da) = (&span.a0, &span.da);
    let mut start = [a0[slot::DEPTH], a0[slot::Q], a0[slot::S], a0[slot::T]];
    let da = [da[slot::DEPTH], da[slot::Q], da[slot::S], da[slot::T]];
    // A span starting left of the row (spans from the fill never do) is clipped at pixel 0, its attributes
    // moved there.
    if span.x0 < 0 {
        let skip = -(span.x0 as f32);
        for (a, d) in start.iter_mut().zip(&da) {
            *a += skip * d;
        }
    }
    let x0 = span.x0.max(0) as usize;
    let run = Run { x0, from: x0.max(from), x1: (span.x1.max(0) as usize).min(to), a0: start, da, in_range };
    walk::<VIS, SRC>(&run, paint, row)
}

/// A paint's `(flat colour, tint, alpha mask)`, as the chunk loops take them.
pub(crate) type PaintColors = (u32, [u32; 3], Option<(f32, f32)>);

/// A fast-path source resolved for the pixel loops: the texture (if any) and
/// `(flat colour, tint, alpha mask)`.
#[derive(Clone, Copy)]
pub(crate) struct Paint<'a> {
    tex: Option<Tex<'a>>,
    colors: (u32, [u32; 3], Option<(f32, f32)>),
}

impl Paint<'_> {
    /// The same paint with flat colour `c` (for the next of a group of flat polygons drawn by one loop).
    #[inline(always)]
    pub(crate) fn with_flat(&self, c: u32) -> Self {
        Self { tex: self.tex, colors: (c, self.colors.1, self.colors.2) }
    }

    /// The flat colour (for a flat source).
    #[inline(always)]
    pub(crate) fn flat(&self) -> u32 {
        self.colors.0
    }

    /// The texture and `(flat colour, tint, alpha mask)`.
    #[inline(always)]
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(crate) fn parts(&self) -> (Option<&Tex<'_>>, &PaintColors) {
        (self.tex.as_ref(), &self.colors)
    }
}

/// Work done by a loop monomorphised for one (visibility, source) pair; [`dispatch`] picks the pair.
pub(crate) trait Fill {
    /// Runs the work with visibility `VIS` and source `SRC`, returning the pixel counts.
    fn fill<const VIS: u8, const SRC: u8>(self, paint: &Paint<'_>) -> SpanCounts;
}

/// Calls `job` with the loop for `source` under `vis`, so nothing is decided per pixel.
#[inline(always)]
pub(crate) fn dispatch(source: Source<'_>, alpha: Option<(f32, f32)>, vis: Visibility, job: impl Fill) -> SpanCounts {
    macro_rules! by_vis {
        ($src:expr, $paint:expr) => {
            match vis {
                Visibility::Overwrite => job.fill::<OVERWRITE, $src>(&$paint),
                Visibility::DepthTest => job.fill::<DEPTH_TEST, $src>(&$paint),
                Visibility::Coverage => job.fill::<COVERAGE, $src>(&$paint),
            }
        };
    }
    match source {
        Source::Flat(c) => by_vis!(FLAT, Paint { tex: None, colors: (c, [0; 3], None) }),
        Source::Texel(t) => by_vis!(TEXEL, Paint { tex: Some(t), colors: (0, [0; 3], alpha) }),
        Source::Tinted(t, tint) => by_vis!(TINTED, Paint { tex: Some(t), colors: (0, tint, alpha) }),
    }
}

/// The pixel colour of a texel for source `SRC`.
#[inline(always)]
fn shade<const SRC: u8>(t: u32, (flat, [cr, cg, cb]): (u32, [u32; 3])) -> u32 {
    match SRC {
        FLAT => flat,
        TINTED => {
            let ch = |shift: u32, c: u32| ((((t >> shift) & 0xff) * c + 32768) >> 16) << shift;
            ch(16, cr) | ch(8, cg) | ch(0, cb)
        }
        _ => t & 0x00ff_ffff,
    }
}

/// The colour the pixel loops below give a pixel whose depth, `1/w`, `s/w` and `t/w` are `a`, or `None`
/// where the alpha mask drops it: the anti-aliased fill shades the pixels an edge crosses with it, so they
/// match the inner runs these loops draw, bit for bit.
#[inline]
pub(crate) fn colour_at(source: Source<'_>, alpha: Option<(f32, f32)>, a: [f32; 4]) -> Option<u32> {
    let (t, tint, tinted) = match source {
        Source::Flat(c) => return Some(c),
        Source::Texel(t) => (t, [0; 3], false),
        Source::Tinted(t, tint) => (t, tint, true),
    };
    let (w, h) = (t.texture.width() as f32, t.texture.height() as f32);
    let setup = Setup { d0: a[0], dd: 0.0, q0: a[1], dq: 0.0, s0: a[2], ds: 0.0, t0: a[3], dt: 0.0, w, h };
    let texel = t.texel_at(&setup, 0.0);
    if let Some((a, cutoff)) = alpha {
        let ta = (texel >> 24) as f32 * (1.0 / 255.0) * a;
        if ta.partial_cmp(&cutoff).is_none_or(std::cmp::Ordering::is_lt) {
            return None;
        }
    }
    Some(if tinted { shade::<TINTED>(texel, (0, tint)) } else { shade::<TEXEL>(texel, (0, tint)) })
}

/// [`colour_at`] of eight pixels of one polygon at once (their depth, `1/w`, `s/w` and `t/w` in `a`), with
/// AVX2 where the CPU has it (bit for bit the same); [`DROPPED`] where the alpha mask drops a pixel.
pub(crate) fn colours_at(source: Source<'_>, alpha: Option<(f32, f32)>, a: &[[f32; 4]; LANES]) -> [u32; LANES] {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = simd::avx2() {
        use crate::render::fill::span_avx2::points::shade_points;
        return match source {
            Source::Flat(c) => [c; LANES],
            Source::Texel(t) => shade_points::<TEXEL>(avx2, a, t, ([0; 3], alpha)),
            Source::Tinted(t, tint) => shade_points::<TINTED>(avx2, a, t, (tint, alpha)),
        };
    }
    std::array::from_fn(|l| colour_at(source, alpha, a[l]).unwrap_or(DROPPED))
}

/// Draws a run: the AVX2 chunk loop where the CPU has it, then (or else) one pixel at a time. The
/// per-pixel loop is the reference the chunk loop must match bit for bit.
#[inline(always)]
pub(crate) fn walk<const VIS: u8, const SRC: u8>(run: &Run, paint: &Paint<'_>, row: &mut Row<'_>) -> SpanCounts {
    let Paint { tex, colors } = *paint;
    let (w, h) = tex.map_or((0.0, 0.0), |t| (t.texture.width() as f32, t.texture.height() as f32));
    let setup = Setup::new(run.a0, run.da, (w, h));
    let (x0, from, x1) = (run.x0, run.from, run.x1);
    // Both loops count in registers: the chunk loop returns its counts packed in a word, the per-pixel loop
    // keeps them in locals (counting through memory costs a store-forwarding stall per span).
    let mut counts = SpanCounts::default();
    let (mut shaded, mut written, mut rejected) = (0u64, 0u64, 0u64);
    let mut x = from;
    #[cfg(target_arch = "x86_64")]
    // Spans of half a chunk or more take the chunk loop (one division for all lanes, no branch per pixel);
    // shorter ones (1-3 pixels, as small polygons give) are cheaper one pixel at a time for a nearest texel
    // from one level. A costly texel (filtered, or a level measured per pixel) is worth a chunk of lanes
    // however short the span, where the row holds a chunk.
    let costly = tex.is_some_and(|t| t.costly()) && row.color.len() >= LANES;
    if (x1.saturating_sub(from) >= LANES / 2 || costly && x1 > from)
        && let Some(avx2) = simd::avx2()
    {
        let (next, packed) = crate::render::fill::span_avx2::chunks::<VIS, SRC>(
            avx2,
            (x0, from, x1),
            &setup,
            paint.tex.as_ref(),
            &paint.colors,
            row,
            run.in_range,
        );
        (x, counts) = (next, packed.unpack());
    }
    let (flat, tint, alpha) = colors;
    for x in x..x1 {
        let k = (x - x0) as f32;
        let depth = setup.depth(k);
        let pass = match VIS {
            // Strictly nearer wins, so on equal depth the polygon drawn first stays (like GL_LESS).
            DEPTH_TEST => row.depth.get(x).is_some_and(|&old| depth > old),
            COVERAGE => row.coverage.get(x >> 6).is_some_and(|&w| w & (1u64 << (x & 63)) == 0),
            _ => true,
        };
        if !pass {
            rejected += 1;
            continue;
        }
        shaded += 1;
        let texel = match tex {
            Some(t) if SRC != FLAT => t.texel_at(&setup, k),
            _ => flat,
        };
        // Alpha mask: the texel's alpha times the polygon's, kept when at least the cutoff (NaN fails).
        if let Some((a, cutoff)) = alpha.filter(|_| SRC != FLAT) {
            let ta = (texel >> 24) as f32 * (1.0 / 255.0) * a;
            if ta.partial_cmp(&cutoff).is_none_or(std::cmp::Ordering::is_lt) {
                continue;
            }
        }
        if let Some(c) = row.color.get_mut(x) {
            *c = shade::<SRC>(texel, (flat, tint));
        }
        match VIS {
            DEPTH_TEST => {
                if let Some(d) = row.depth.get_mut(x) {
                    *d = depth;
                }
            }
            COVERAGE => {
                if let Some(w) = row.coverage.get_mut(x >> 6) {
                    *w |= 1u64 << (x & 63);
                }
            }
            _ => {}
        }
        written += 1;
    }
    SpanCounts {
        shaded: counts.shaded + shaded,
        written: counts.written + written,
        rejected: counts.rejected + rejected,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::mip::TexGradients;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
    use crate::render::core::vertex::ATTRS;
    use crate::render::fill::row::{cover_bits, coverage_byte};
    use crate::render::simd::{force_portable, has_avx2};

    /// A random attribute value; when `hostile`, one in six is NaN, infinite, huge or zero.
    fn float(rng: &mut Lcg, hostile: bool) -> f32 {
        if hostile && rng.below(6) == 0 {
            [f32::NAN, f32::INFINITY, -f32::INFINITY, 3e9, -3e9, 0.0][rng.below(6) as usize]
        } else {
            (rng.next() as f32 / u32::MAX as f32 - 0.3) * 4.0
        }
    }

    /// Draws a span with the given path and returns the row's buffers and the counts.
    fn run(
        span: &Span,
        source: Source<'_>,
        alpha: Option<(f32, f32)>,
        vis: Visibility,
        start: (&[u32], &[f32], &[u64]),
        portable: bool,
    ) -> (Vec<u32>, Vec<u32>, Vec<u64>, SpanCounts) {
        let (mut color, mut depth, mut coverage) = (start.0.to_vec(), start.1.to_vec(), start.2.to_vec());
        force_portable(portable);
        let counts =
            draw(span, source, alpha, vis, &mut Row { color: &mut color, depth: &mut depth, coverage: &mut coverage });
        force_portable(false);
        (color, depth.iter().map(|d| d.to_bits()).collect(), coverage, counts)
    }

    #[test]
    fn chunk_loop_matches_the_per_pixel_loop_bit_for_bit() {
        if !has_avx2() {
            eprintln!("no AVX2 on this CPU: only the per-pixel loop runs, nothing to compare");
            return;
        }
        let mut rng = Lcg(7);
        let wraps = [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat];
        for case in 0..3000 {
            let hostile = case % 4 == 3;
            let (tw, th) = ([1u32, 4, 16, 64, 5, 100][rng.below(6) as usize], [1u32, 8, 32, 3][rng.below(4) as usize]);
            let texels: Vec<u32> = (0..tw * th).map(|_| rng.next()).collect();
            let Ok(tex) = Texture::new(tw, th, texels) else { panic!("texture") };
            let sampler = Sampler { wrap_s: wraps[rng.below(3) as usize], wrap_t: wraps[rng.below(3) as usize] };
            let width = [3usize, 8, 13, 64, 70, 130][rng.below(6) as usize];
            let x0 = rng.below(width as u32) as i32;
            let x1 = x0 + 1 + rng.below((width as i32 - x0) as u32) as i32;
            let mut a0 = [0.0; ATTRS];
            let mut da = [0.0; ATTRS];
            for i in 0..ATTRS {
                a0[i] = float(&mut rng, hostile);
                da[i] = float(&mut rng, hostile) * 0.05;
            }
            a0[slot::Q] = a0[slot::Q].abs() + 0.1;
            let span = Span { y: 0, x0, x1, a0, da };
            let color: Vec<u32> = (0..width).map(|_| rng.next()).collect();
            let depth: Vec<f32> = (0..width).map(|_| float(&mut rng, hostile)).collect();
            // Random words, and often whole words drawn (which the chunk loop skips at once).
            let coverage: Vec<u64> = (0..width.div_ceil(64))
                .map(|_| match rng.below(3) {
                    0 => u64::MAX,
                    1 => u64::MAX << rng.below(64),
                    _ => u64::from(rng.next()) << 32 | u64::from(rng.next()),
                })
                .collect();
            let tint = [rng.below(65537), rng.below(65537), rng.below(65537)];
            let alpha = (rng.below(2) == 0).then(|| (float(&mut rng, hostile), float(&mut rng, false) * 0.3));
            let t = Tex::polygon(&tex, sampler, Filter::Nearest, 0.0);
            // Gradients that give level changes within a chunk, or one level for all of it, or (hostile)
            // none that can be measured.
            let scale = [0.002, 0.05, 1.0][rng.below(3) as usize];
            let mut gradient = || std::array::from_fn(|_| float(&mut rng, hostile) * scale);
            let g = TexGradients { dx: gradient(), dy: gradient() };
            let filters = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear, Filter::Anisotropic(8), Filter::Area];
            let filter = filters[rng.below(5) as usize];
            let lod = float(&mut rng, hostile) * 2.0;
            // A level for each pixel, or a filtered level (or two) for the polygon; `area` measures its
            // footprint at each pixel.
            let levels = match rng.below(2) {
                _ if filter == Filter::Area => Tex::per_pixel(&tex, sampler, filter, g),
                0 => Tex::per_pixel(&tex, sampler, filter, g),
                _ => Tex::polygon(&tex, sampler, filter, lod),
            };
            let sources = [
                Source::Flat(rng.next()),
                Source::Texel(t),
                Source::Tinted(t, tint),
                Source::Texel(levels),
                Source::Tinted(levels, tint),
            ];
            for source in sources {
                for vis in [Visibility::Overwrite, Visibility::DepthTest, Visibility::Coverage] {
                    let start = (&color[..], &depth[..], &coverage[..]);
                    let fast = run(&span, source, alpha, vis, start, false);
                    let slow = run(&span, source, alpha, vis, start, true);
                    assert_eq!(
                        fast, slow,
                        "case {case}, {vis:?}, span {x0}..{x1} of {width}, {tw}x{th} {sampler:?} {filter}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_span_starting_left_of_the_row_is_clipped_with_its_attributes_moved() {
        let mut a0 = [0.0; ATTRS];
        let mut da = [0.0; ATTRS];
        (a0[slot::DEPTH], da[slot::DEPTH]) = (1.0, 0.25);
        let draw_from = |x0: i32, a0: [f32; ATTRS]| {
            let (mut color, mut depth) = (vec![0u32; 8], vec![2.5f32; 8]);
            let span = Span { y: 0, x0, x1: 6, a0, da };
            let counts = draw(
                &span,
                Source::Flat(7),
                None,
                Visibility::DepthTest,
                &mut Row { color: &mut color, depth: &mut depth, coverage: &mut [] },
            );
            (color, depth, counts)
        };
        let mut clipped = a0;
        clipped[slot::DEPTH] += 3.0 * 0.25;
        let (color, depth, counts) = draw_from(-3, a0);
        assert_eq!((color.clone(), depth.clone(), counts), draw_from(0, clipped));
        // Depths 1.75, 2.0, 2.25 fail against 2.5 on pixels 0..3; 2.5 fails (not nearer); 2.75, 3.0 pass.
        assert_eq!(color, [0, 0, 0, 0, 7, 7, 0, 0]);
        assert_eq!(counts, SpanCounts { shaded: 2, written: 2, rejected: 4 });
    }

    #[test]
    fn a_span_passing_the_row_end_stops_there_under_every_source() {
        let Ok(tex) = Texture::new(8, 8, (1..=64).map(|i| 0xff00_0000 | (i * 0x0001_0101)).collect()) else {
            panic!("texture")
        };
        let g = TexGradients { dx: [0.0, 0.01, 0.0], dy: [0.0, 0.0, 0.01] };
        let mut a0 = [0.0; ATTRS];
        a0[slot::Q] = 1.0;
        let span = Span { y: 0, x0: 14, x1: 18, a0, da: [0.0; ATTRS] };
        for t in [
            Tex::polygon(&tex, Sampler::default(), Filter::Nearest, 0.0),
            Tex::per_pixel(&tex, Sampler::default(), Filter::Trilinear, g),
        ] {
            // A short span with a costly texel enters the chunk loop, whose last chunk is moved back inside
            // the row: it must not be moved back for ever, and must draw what the per-pixel loop draws.
            let draw = |portable| {
                run(&span, Source::Texel(t), None, Visibility::Overwrite, (&[0; 16], &[0.0; 16], &[0]), portable)
            };
            let (color, _, _, counts) = draw(false);
            assert_eq!(color[..14], [0; 14]);
            assert!(color[14..].iter().all(|&c| c != 0), "{color:?}");
            assert_eq!((color, counts), {
                let (c, _, _, n) = draw(true);
                (c, n)
            });
        }
    }

    #[test]
    fn coverage_bytes_straddle_words() {
        let mut cov = vec![0u64; 3];
        cover_bits(&mut cov, 60, 0xff);
        assert_eq!(cov, [0xf << 60, 0xf, 0]);
        assert_eq!(coverage_byte(&cov, 60), 0xff);
        assert_eq!(coverage_byte(&cov, 62), 0x3f);
        assert_eq!(coverage_byte(&cov, 56), 0xf0);
        assert_eq!(coverage_byte(&cov, 64), 0x0f);
        // Past the end reads as drawn, so nothing is written there.
        assert_eq!(coverage_byte(&cov, 190), 0xfc);
    }
}
