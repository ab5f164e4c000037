//! Spans drawn depth first against the per-pixel loop, bit for bit.

use super::SPANS;
use crate::render::core::test_rng::Lcg;
use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::core::vertex::{ATTRS, slot};
use crate::render::fill::row::{Row, SpanCounts, Visibility};
use crate::render::fill::scanline::Span;
use crate::render::fill::span_lanes::{Source, draw};
use crate::render::fill::texel::Tex;
use crate::render::simd::{force_portable, has_avx2};

/// A row's colours, depths (as bits) and counts after drawing `span` from `start`, with the vector loops
/// or (`portable`) the per-pixel loop only.
fn run(
    span: &Span,
    source: Source<'_>,
    alpha: Option<(f32, f32)>,
    start: (&[u32], &[f32]),
    portable: bool,
) -> (Vec<u32>, Vec<u32>, SpanCounts) {
    let (mut color, mut depth) = (start.0.to_vec(), start.1.to_vec());
    force_portable(portable);
    let row = &mut Row { color: &mut color, depth: &mut depth, coverage: &mut [] };
    let counts = draw(span, source, alpha, Visibility::DepthTest, row);
    force_portable(false);
    (color, depth.iter().map(|d| d.to_bits()).collect(), counts)
}

#[test]
fn long_spans_drawn_depth_first_match_the_per_pixel_loop_bit_for_bit() {
    if !has_avx2() {
        eprintln!("no AVX2 on this CPU: only the per-pixel loop runs, nothing to compare");
        return;
    }
    let mut rng = Lcg(31);
    let wraps = [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat];
    SPANS.with(|n| n.set(0));
    let (mut drawn, mut hidden) = (0u64, 0u64);
    for case in 0..1500 {
        // Rows up to several blocks of chunks long, most of them no multiple of a chunk (the last chunk is
        // moved back over the one before); textures of power-of-two and other sizes.
        let width = [8usize, 61, 127, 128, 129, 300, 777, 1283][rng.below(8) as usize];
        let (tw, th) = ([1u32, 16, 64, 5, 100][rng.below(5) as usize], [1u32, 8, 32, 3][rng.below(4) as usize]);
        let Ok(tex) = Texture::new(tw, th, (0..tw * th).map(|_| rng.next()).collect()) else { panic!("texture") };
        let sampler = Sampler { wrap_s: wraps[rng.below(3) as usize], wrap_t: wraps[rng.below(3) as usize] };
        let x0 = rng.below(width as u32 / 4) as i32;
        let x1 = x0 + 1 + rng.below((width as i32 - x0) as u32) as i32;
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
        let span = Span { y: 0, x0, x1, a0, da };
        let color: Vec<u32> = (0..width).map(|_| rng.next()).collect();
        // Depths in front and behind, in runs, so that chunks pass whole, in part and not at all.
        let mut depth = vec![0.0f32; width];
        let mut x = 0;
        while x < width {
            let (run, z) = (1 + rng.below(40) as usize, rng.unit());
            depth[x..(x + run).min(width)].fill(z);
            x += run;
        }
        let t = Tex::polygon(&tex, sampler, Filter::Nearest, 0.0);
        let tint = [rng.below(65537), rng.below(65537), rng.below(65537)];
        let alpha = (rng.below(4) == 0).then(|| (rng.unit(), rng.unit() * 0.5));
        for source in [Source::Texel(t), Source::Tinted(t, tint)] {
            let fast = run(&span, source, alpha, (&color, &depth), false);
            let slow = run(&span, source, alpha, (&color, &depth), true);
            assert_eq!(fast, slow, "case {case}: span {x0}..{x1} of {width}, {tw}x{th} {sampler:?}, alpha {alpha:?}");
            (drawn, hidden) = (drawn + fast.2.written, hidden + fast.2.rejected);
        }
    }
    let spans = SPANS.with(std::cell::Cell::get);
    assert!(spans > 400 && drawn > 100_000 && hidden > 100_000, "{spans} spans, {drawn} drawn, {hidden} hidden");
}
