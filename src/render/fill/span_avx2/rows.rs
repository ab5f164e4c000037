//! A polygon's spans of a band drawn by one chunk loop that runs on from one row's last chunk to the next
//! row's first.
//!
//! Why: on courses of many small polygons (the mountain's trees) most spans are one or two chunks long, and
//! a loop a span ends with a branch on its length that the CPU mispredicts about once a span, losing the
//! overlap of one span's chunks with the next's. Here a row's end only picks which run the next chunk
//! reads its set-up from. The set-up is read from memory every chunk instead of staying in registers, so
//! long spans keep the loop a span (`chunks_avx2`): the caller decides
//! ([`polygon_spans`](crate::render::fill::polygon_spans)).

use crate::render::simd::x86::span::*;

use super::chunk::{ChunkPixels, ChunkSpan};
use crate::render::core::mip::{LOG2_QUARTIC, TexGradients};
use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::fill::row::{
    BandPixels, COVERAGE, DEPTH_TEST, FLAT, LANES, PackedCounts, RowRun, Setup, TINTED, cover_bits, coverage_byte,
};
use crate::render::fill::texel::Tex;
use crate::render::simd::Avx2;
use crate::render::simd::x86::{load8, store8};

/// Draws every run of `runs`, rows of band `px` (each run inside the frame's width and non-empty), and
/// returns their counts; draws nothing when the frame is narrower than a chunk.
pub(crate) fn rows<const VIS: u8, const SRC: u8>(
    _: Avx2,
    runs: &[RowRun],
    tex: Option<&Tex<'_>>,
    colors: &(u32, [u32; 3], Option<(f32, f32)>),
    px: &mut BandPixels<'_>,
) -> PackedCounts {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all `rows_avx2` needs.
    #[allow(unsafe_code)]
    unsafe {
        rows_avx2::<VIS, SRC>(runs, tex, colors, px)
    }
}

/// [`rows`]'s body, compiled for AVX2.
#[target_feature(enable = "avx2")]
fn rows_avx2<const VIS: u8, const SRC: u8>(
    runs: &[RowRun],
    tex: Option<&Tex<'_>>,
    &(flat, tint, alpha): &(u32, [u32; 3], Option<(f32, f32)>),
    px: &mut BandPixels<'_>,
) -> PackedCounts {
    let mut counts = PackedCounts::default();
    let (width, words) = (px.width, px.words);
    let (Some(mut run), true) = (runs.first(), width >= LANES) else { return counts };
    let mut next_run = 0;
    let mut x = run.x0;
    'runs: loop {
        debug_assert!(run.x0 < run.x1 && run.x1 <= width, "a run {}..{} in a row of {width}", run.x0, run.x1);
        debug_assert!(run.y >= px.y0 && (run.y - px.y0 + 1) * width <= px.color.len(), "row {} not in the band", run.y);
        let r = run.y.wrapping_sub(px.y0);
        let span = ChunkSpan { x0: run.x0, x1: run.x1, s: &run.setup, in_range: SRC != FLAT && run.in_range };
        let pixels = ChunkPixels { color: &mut *px.color, depth: &mut *px.depth, base: r * width, width };
        let coverage = if VIS == COVERAGE { px.coverage.get_mut(r * words..(r + 1) * words) } else { None };
        chunk_x8!('runs, VIS, SRC, &mut x, span, (tex, flat, tint, alpha), pixels, coverage.unwrap_or(&mut []), &mut counts);
        // The next chunk: further along this row, or the next run's first (which run is read is all that
        // depends on it). A run past the row's end (never one from the walk) ends at it, or the last chunk
        // would be moved back to end inside the row again and again.
        let done = x >= run.x1.min(width);
        next_run += usize::from(done);
        let Some(next) = runs.get(next_run) else { break };
        run = next;
        x = if done { run.x0 } else { x };
    }
    counts
}
