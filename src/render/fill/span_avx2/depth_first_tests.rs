//! Spans drawn depth first against the per-pixel loop, bit for bit.

use super::{ONE_ROW, PIXELS};
use crate::render::core::test_rng::Lcg;
use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::core::vertex::{ATTRS, slot};
use crate::render::fill::row::{Row, SpanCounts, Visibility};
use crate::render::fill::scanline::Span;
use crate::render::fill::span_lanes::{Fill, Paint, Source, dispatch, span_run};
use crate::render::fill::texel::Tex;
use crate::render::simd::{force_portable, has_avx2};

/// A span drawn from pixel `from` on (the pixels before it known to fail the depth test).
struct From<'s, 'r, 'b>(&'s Span, usize, &'r mut Row<'b>);

impl Fill for From<'_, '_, '_> {
    fn fill<const VIS: u8, const SRC: u8>(self, paint: &Paint<'_>) -> SpanCounts {
        span_run::<VIS, SRC>(self.0, paint, self.2, false, (self.1, usize::MAX))
    }
}

/// A row's colours, depths (as bits) and counts after drawing `span` from pixel `from` over `start`, with
/// the vector loops or (`portable`) the per-pixel loop only.
fn run(
    (span, from): (&Span, usize),
    (source, alpha): (Source<'_>, Option<(f32, f32)>),
    start: (&[u32], &[f32]),
    portable: bool,
) -> (Vec<u32>, Vec<u32>, SpanCounts) {
    let (mut color, mut depth) = (start.0.to_vec(), start.1.to_vec());
    force_portable(portable);
    let row = &mut Row { color: &mut color, depth: &mut depth, coverage: &mut [] };
    let counts = dispatch(source, alpha, Visibility::DepthTest, From(span, from, row));
    force_portable(false);
    (color, depth.iter().map(|d| d.to_bits()).collect(), counts)
}

/// Whether a level of `size` texels folded by `wrap` (on both axes) is drawn depth first.
fn folded(size: (u32, u32), sampler: Sampler) -> bool {
    let fold = |n: u32, w: Wrap| n <= 1 << 16 && (w == Wrap::ClampToEdge || w == Wrap::Repeat && n.is_power_of_two());
    fold(size.0, sampler.wrap_s) && fold(size.1, sampler.wrap_t)
}

// long: one scenario over the spans, textures and rows the depth-first loop takes or hands back.
#[test]
fn long_spans_drawn_depth_first_match_the_per_pixel_loop_bit_for_bit() {
    if !has_avx2() {
        eprintln!("no AVX2 on this CPU: only the per-pixel loop runs, nothing to compare");
        return;
    }
    let mut rng = Lcg(31);
    let wraps = [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat];
    PIXELS.with(|n| n.set(0));
    ONE_ROW.with(|n| n.set(0));
    let (mut expected, mut at_most) = (0u64, 0u64);
    for case in 0..1500 {
        // Rows up to several blocks of chunks long, most of them no multiple of a chunk (the last chunk is
        // moved back over the one before); textures of power-of-two and other sizes, now and then one whose
        // columns or rows fill the 16 bits kept between the passes, or one past them.
        let width = [8usize, 61, 127, 128, 129, 300, 777, 1283][rng.below(8) as usize];
        let (tw, th) = match case % 100 {
            0 => (65_536, 2),
            1 => (1, 65_536),
            2 => (65_537, 1),
            _ => ([1u32, 16, 64, 5, 100][rng.below(5) as usize], [1u32, 8, 32, 3][rng.below(4) as usize]),
        };
        let Ok(tex) = Texture::new(tw, th, (0..tw * th).map(|_| rng.next()).collect()) else { panic!("texture") };
        let sampler = Sampler { wrap_s: wraps[rng.below(3) as usize], wrap_t: wraps[rng.below(3) as usize] };
        let x0 = rng.below(width as u32 / 4) as i32;
        let x1 = x0 + 1 + rng.below((width as i32 - x0) as u32) as i32;
        // A third of the spans drawn from a pixel past their start.
        let from = if case % 3 == 0 { x0 as usize + rng.below((x1 - x0) as u32) as usize } else { x0 as usize };
        let (mut a0, mut da) = ([0.0; ATTRS], [0.0; ATTRS]);
        a0[slot::DEPTH] = rng.unit();
        da[slot::DEPTH] = (rng.unit() - 0.5) * 0.004;
        a0[slot::Q] = 0.2 + rng.unit();
        da[slot::Q] = (rng.unit() - 0.5) * 0.001;
        // Texel coordinates small or far out (past the range the loops take without checks), or NaN.
        let reach = [1.0, 40.0, 1e7][rng.below(3) as usize];
        (a0[slot::S], a0[slot::T]) = ((rng.unit() - 0.5) * reach, (rng.unit() - 0.5) * reach);
        (da[slot::S], da[slot::T]) = ((rng.unit() - 0.5) * 0.05, (rng.unit() - 0.5) * 0.05);
        if case % 50 == 49 {
            a0[slot::S] = f32::NAN;
        }
        // A quarter of the spans along a texture's row (the row fixed, the column changing at most a texel a
        // pixel), whose chunks read their texels from one row where they can.
        if case % 4 == 1 {
            (da[slot::Q], da[slot::T]) = (0.0, 0.0);
            da[slot::S] = (rng.unit() - 0.5) * 1.8 * a0[slot::Q] / tw as f32;
        }
        let span = Span { y: 0, x0, x1, a0, da };
        let color: Vec<u32> = (0..width).map(|_| rng.next()).collect();
        // Depths in front and behind, in runs, so that chunks pass whole, in part and not at all; one row in
        // ten has a depth row shorter than its colours (the chunk loop stops where it ends).
        let short = case % 10 == 5;
        let mut depth = vec![0.0f32; if short { width - 5 } else { width }];
        let mut x = 0;
        while x < depth.len() {
            let (run, z) = (1 + rng.below(40) as usize, rng.unit());
            let end = (x + run).min(depth.len());
            depth[x..end].fill(z);
            x = end;
        }
        // Nearest and bilinear texels, both drawn depth first; trilinear (two levels) never.
        let filter = [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][rng.below(3) as usize];
        let t = Tex::polygon(&tex, sampler, filter, if filter == Filter::Trilinear { 0.7 } else { 0.0 });
        let tint = [rng.below(65537), rng.below(65537), rng.below(65537)];
        let alpha = (rng.below(4) == 0).then(|| (rng.unit(), rng.unit() * 0.5));
        for source in [Source::Texel(t), Source::Tinted(t, tint)] {
            let fast = run((&span, from), (source, alpha), (&color, &depth), false);
            let slow = run((&span, from), (source, alpha), (&color, &depth), true);
            let what = format!("case {case}: span {x0}..{x1} from {from} of {width}, {tw}x{th} {sampler:?} {filter:?}");
            assert_eq!(fast, slow, "{what}, alpha {alpha:?}");
            // The spans the chunk loop takes (half a chunk or more; any length for filtered texels, where the
            // row holds a chunk), on the path's textures, without alpha.
            let level = (t.texture.width(), t.texture.height());
            let one_level = filter != Filter::Trilinear;
            let long = x1 as usize - from >= 4 || filter != Filter::Nearest && width >= 8 && x1 as usize > from;
            let taken = alpha.is_none() && one_level && folded(level, sampler) && long;
            let n = if taken { (x1 as usize - from) as u64 } else { 0 };
            (expected, at_most) = if short { (expected, at_most + n) } else { (expected + n, at_most + n) };
        }
    }
    // Every pixel of the spans the path takes went through it, all but the short depth rows' whole.
    let pixels = PIXELS.with(std::cell::Cell::get);
    assert!((expected..=at_most).contains(&pixels) && expected > 50_000, "{pixels} pixels, {expected}..={at_most}");
    // And the spans along a row read most of their chunks from it.
    let one_row = ONE_ROW.with(std::cell::Cell::get);
    assert!(one_row > 150, "{one_row} chunks read from one row");
}
