//! A long span of nearest or bilinear texels behind a depth test, drawn depth first: a block of chunks is
//! depth-tested and its texels found, then its texels are read and its colours written.
//!
//! Why: in the one-pass chunk loop each chunk is one chain (the divide, the texel coordinates, eight loads
//! that wait for them, the colour that waits for the loads), long enough that the CPU overlaps little of
//! one chunk with the next: a full-screen textured quad took half the time with its texel loads left
//! out. Here the
//! first pass is arithmetic alone and the second gathers its texels from the columns and rows it kept in a
//! small buffer, so the reads of a chunk no longer wait on its own arithmetic and the chunks of a pass
//! overlap.
//!
//! Where a span's texels lie along a texture row, at most a texel a pixel (a magnified texture, as most of
//! `ultra`'s nearest texels are), the second pass reads a chunk's eight from one row with one load and a
//! permute instead of a gather, whenever they fall within eight columns ([`one_row_direction`] says which
//! spans try, so that others never pay for the check).
//!
//! Bilinear texels (the minified polygons of `min-bilinear`, `area` and the presets above `low`) take
//! the same two passes: the first keeps each lane's two columns, two rows and two weights, the second
//! gathers the four texels and blends them.
//!
//! Every pixel gets the operations of the one-pass loop ([`chunk_x8`](super::chunk)) in the same order,
//! so the frames are bit-identical. Only the order of the writes between chunks changes: a block's depths
//! are written in the first pass and its colours in the second. A chunk moved back to end inside the row
//! shares pixels with the chunk before, which it leaves as they are (lanes before its start are masked
//! off); each pass reads what it blends over just before writing it, so those pixels keep what the chunk
//! before wrote.
//!
//! The short spans a polygon draws across rows ([`rows`](super::rows)) keep the one-pass loop: drawn depth
//! first too they gained nothing beside the long spans' gain (`render` of the exported frames, 1280x720,
//! 1 thread, best of 7 alternated rounds: the city 0.910x against 0.915x, the mountain 0.964x against
//! 0.968x, its trees alone 1.02x against 1.01x). So do alpha-masked polygons, whose depths wait for their
//! texels: drawn depth first (their depths written in the second pass) the mountain's frames took 1.04x
//! and its trees alone 1.05x.

use crate::render::simd::x86::span::*;

use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::fill::row::{DEPTH_TEST, FLAT, LANES, PackedCounts, Row, Setup, TINTED};
use crate::render::fill::texel::Tex;
use crate::render::simd::x86::{ONE_ROW_WIDTH, gather_texels, load8, one_row_texels, store8};

/// Chunks of a block: their positions, masks and texels' columns and rows (and weights, bilinear) wait
/// between the passes in a buffer of this many (1.5 KiB nearest, 2.5 KiB bilinear).
const BLOCK: usize = 16;

/// Draws span pixels `from..x1` (attributes counted from `x0`) of `row` as `chunks_avx2` draws them, and
/// returns where it stopped (`x1` unless the row is too short for a chunk) and its counts, when the span is
/// one drawn here: a depth test, nearest or bilinear texels of one level, no alpha mask and source `SRC`
/// texel or tinted, the texture's wrap modes folded in lanes (not mirrored, nor repeated at a size that is
/// no power of two: the one-pass loop reads those a lane at a time), its level at most 65,536 texels a side
/// and within one gather's reach; `None`, having drawn nothing, for any other.
#[target_feature(enable = "avx2")]
pub(crate) fn span<const VIS: u8, const SRC: u8>(
    range: (usize, usize, usize),
    (s, in_range): (&Setup, bool),
    tex: Option<&Tex<'_>>,
    (tint, alpha): ([u32; 3], Option<(f32, f32)>),
    row: &mut Row<'_>,
) -> Option<(usize, PackedCounts)> {
    if VIS != DEPTH_TEST || SRC == FLAT || alpha.is_some() {
        return None;
    }
    let t = tex.filter(|t| t.per_pixel.is_none() && t.coarser.is_none())?;
    let (texture, sampler) = (t.texture, t.sampler);
    let size = (texture.width(), texture.height());
    let zero = _mm256_setzero_si256();
    // A column and a row each fit 16 bits of a lane between the passes, and the level fits one gather.
    let fits = size.0 <= 1 << 16
        && size.1 <= 1 << 16
        && u64::from(size.0) * u64::from(size.1) <= texture.texels().len().min(i32::MAX as usize) as u64;
    if !fits || wrap_x8!(zero, size.0, sampler.wrap_s).is_none() || wrap_x8!(zero, size.1, sampler.wrap_t).is_none() {
        return None;
    }
    let done = match t.filter {
        Filter::Nearest => nearest::<SRC>(range, (s, in_range), (texture, sampler), tint, row),
        Filter::Bilinear => bilinear::<SRC>(range, (s, in_range), (texture, sampler), tint, row),
        _ => return None,
    };
    #[cfg(test)]
    PIXELS.with(|n| n.set(n.get() + done.1.unpack().shaded + done.1.unpack().rejected));
    Some(done)
}

/// The two passes over span pixels `from..x1` (attributes counted from `x0`, set up by `s`) of `row`, a
/// block of chunks at a time, evaluating to where they stopped and their counts: `$texel` says where the
/// texels are of the chunk at offsets `$k` (`None` stops the loop, which hands the rest to the caller's
/// per-pixel loop), `$write` draws `$block`'s colours into the row's `$color`; `$empty` is an unused
/// entry's texel part. A macro rather than a function taking closures: that took the circuit's frames to
/// 1.08x the time.
macro_rules! two_passes {
    (
        $range:expr, $s:expr, $row:expr, $empty:expr,
        |$k:ident| $texel:expr,
        |$block:ident, $color:ident| $write:expr
    ) => {{
        let ((x0, from, x1), s, row): ((usize, usize, usize), &Setup, &mut Row<'_>) = ($range, $s, $row);
        let width = row.color.len();
        let (mut x, end) = (from, x1.min(width));
        let mut counts = PackedCounts::default();
        let zero = _mm256_setzero_si256();
        let mut block = [(0usize, zero, $empty); BLOCK];
        let mut stopped = false;
        while x < end && width >= LANES && !stopped {
            // Depth first: each chunk's test and depths, and where the texels are of those with a pixel to
            // draw.
            let mut kept = 0;
            while kept < BLOCK && x < end {
                let c = if x + LANES <= width { x } else { width - LANES };
                let lane = _mm256_add_epi32(_mm256_set1_epi32(c as i32), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
                let valid = _mm256_and_si256(
                    _mm256_cmpgt_epi32(lane, _mm256_set1_epi32(x as i32 - 1)),
                    _mm256_cmpgt_epi32(_mm256_set1_epi32(x1 as i32), lane),
                );
                let $k = _mm256_cvtepi32_ps(_mm256_sub_epi32(lane, _mm256_set1_epi32(x0 as i32)));
                let depth = _mm256_add_ps(_mm256_set1_ps(s.d0), _mm256_mul_ps($k, _mm256_set1_ps(s.dd)));
                // Where the buffers are too short for the chunk (no caller's are), the caller's per-pixel
                // loop draws the rest, as after the one-pass loop.
                let (Some(old), true) = (row.depth.get(c..).and_then(load8::<f32, __m256>), c + LANES <= width) else {
                    stopped = true;
                    break;
                };
                let pass = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(depth, old)), valid);
                let lanes = |m: __m256i| u64::from((_mm256_movemask_ps(_mm256_castsi256_ps(m)) as u32).count_ones());
                let n = lanes(pass);
                let rejected = lanes(valid) - n;
                if n == 0 {
                    counts.add(0, 0, rejected);
                    x = c + LANES;
                    continue;
                }
                let Some(at) = ($texel) else {
                    stopped = true;
                    break;
                };
                if let Some(out) = row.depth.get_mut(c..) {
                    store8(out, _mm256_blendv_ps(old, depth, _mm256_castsi256_ps(pass)));
                }
                counts.add(n, n, rejected);
                x = c + LANES;
                block[kept] = (c, pass, at);
                kept += 1;
            }
            // Then the texels, read from where the first pass found them, and the colours.
            let ($block, $color) = (&block[..kept], &mut *row.color);
            $write;
        }
        (x.min(x1), counts)
    }};
}

/// [`span`]'s loop for nearest texels of `texture`, a level `span` checked.
#[target_feature(enable = "avx2")]
fn nearest<const SRC: u8>(
    range: (usize, usize, usize),
    (s, in_range): (&Setup, bool),
    (texture, sampler): (&Texture, Sampler),
    tint: [u32; 3],
    row: &mut Row<'_>,
) -> (usize, PackedCounts) {
    let (tw, th) = (texture.width(), texture.height());
    let one_row = in_range.then(|| one_row_direction(s, range, (tw, th))).flatten();
    two_passes!(
        range,
        s,
        row,
        _mm256_setzero_si256(),
        |k| {
            let (_, u, v) = coordinates_x8!(s, k);
            let (xi, yi) = texel_xy_x8!(u, v, (tw, th), in_range);
            match (wrap_x8!(xi, tw, sampler.wrap_s), wrap_x8!(yi, th, sampler.wrap_t)) {
                (Some(wx), Some(wy)) => Some(_mm256_or_si256(wx, _mm256_slli_epi32::<16>(wy))),
                _ => None,
            }
        },
        |block, color| write_nearest::<SRC>(block, (texture, one_row), tint, color)
    )
}

/// Whether the texels of a span (pixels `from..x1` with attributes counted from `x0`, set up by `s`) lie
/// on one row eight pixels at a time, mostly, in a level `(tw, th)` texels in size: `Some(ascending)`
/// when along the span the column changes by at most one texel a pixel (rising when `ascending`) and the
/// row by at most 1/32 of a texel, so that [`one_row_texels`] nearly always takes the eight; `None`
/// otherwise, and the gathers are not kept waiting on a check that would fail.
///
/// `u = (s0 + k ds) / (q0 + k dq)` changes by `(ds q0 - s0 dq) / q^2` a pixel, so (with `q` linear and
/// positive at both ends of the span, so between them) most where `q` is least, at one end.
fn one_row_direction(s: &Setup, (x0, from, x1): (usize, usize, usize), (tw, th): (u32, u32)) -> Option<bool> {
    let q_at = |x: usize| s.q0 + (x as f32 - x0 as f32) * s.dq;
    let q = q_at(from).min(q_at(x1));
    // Not positive or NaN: no bound (and no claim).
    if q.is_nan() || q <= 0.0 || tw >= ONE_ROW_WIDTH {
        return None;
    }
    let per_q2 = 1.0 / (q * q);
    let du = (s.ds * s.q0 - s.s0 * s.dq) * tw as f32 * per_q2;
    let dv = (s.dt * s.q0 - s.t0 * s.dq) * th as f32 * per_q2;
    (du.abs() <= 1.0 && dv.abs() <= 1.0 / 32.0).then_some(du >= 0.0)
}

/// [`span`]'s loop for bilinear texels of `texture`, a level `span` checked: the first pass keeps each lane's
/// two columns, two rows and two weights, 16 bits each.
#[target_feature(enable = "avx2")]
fn bilinear<const SRC: u8>(
    range: (usize, usize, usize),
    (s, in_range): (&Setup, bool),
    (texture, sampler): (&Texture, Sampler),
    tint: [u32; 3],
    row: &mut Row<'_>,
) -> (usize, PackedCounts) {
    let size = (texture.width(), texture.height());
    let pack = |x: __m256i, y: __m256i| _mm256_or_si256(x, _mm256_slli_epi32::<16>(y));
    two_passes!(
        range,
        s,
        row,
        [_mm256_setzero_si256(); 3],
        |k| {
            let (_, u, v) = coordinates_x8!(s, k);
            let ((x, y), (ax, ay)) = bilinear_corner_x8!(u, v, size, in_range);
            bilinear_wrap_x8!(x, y, size, sampler).map(|((x, x1), (y, y1))| [pack(x, y), pack(x1, y1), pack(ax, ay)])
        },
        |block, color| write_bilinear::<SRC>(block, texture, tint, color)
    )
}

/// Paints a chunk's `texel`s (tinted by `tint` when `SRC` is [`TINTED`]) over pixels `c..c + 8` of `color`
/// where `pass` holds.
macro_rules! paint_over {
    ($src:expr, $color:expr, $c:expr, $pass:expr, $texel:expr, $tint:expr) => {{
        let (color, c, pass, texel): (&mut [u32], usize, __m256i, __m256i) = ($color, $c, $pass, $texel);
        if let Some(old) = color.get(c..).and_then(load8::<u32, __m256i>) {
            let paint = if $src == TINTED {
                tint_x8!(texel, $tint)
            } else {
                _mm256_and_si256(texel, _mm256_set1_epi32(0x00ff_ffff))
            };
            if let Some(out) = color.get_mut(c..) {
                store8(out, _mm256_blendv_epi8(old, paint, pass));
            }
        }
    }};
}

/// The second pass over a block of chunks `(column, pass mask, texel)` (each lane's texel column in its low
/// 16 bits, its row in its high 16): each chunk's texels gathered from `texture` and painted over `color`.
///
/// Gathered, where the one-pass loop loads a lane at a time: with no arithmetic waiting on them the eight
/// reads cost less as one gather (a full-screen textured quad 0.71x the one-pass loop's time, against 0.82x
/// with eight loads).
#[inline]
#[target_feature(enable = "avx2")]
fn write_nearest<const SRC: u8>(
    block: &[(usize, __m256i, __m256i)],
    (texture, one_row): (&Texture, Option<bool>),
    tint: [u32; 3],
    color: &mut [u32],
) {
    let (texels, size) = (texture.texels(), (texture.width(), texture.height()));
    for &(c, pass, texel) in block {
        if let Some(texel) = one_row.and_then(|ascending| one_row_texels(texels, size.0, texel, ascending)) {
            #[cfg(test)]
            ONE_ROW.with(|n| n.set(n.get() + 1));
            paint_over!(SRC, color, c, pass, texel, tint);
            continue;
        }
        let (x, y) = (_mm256_and_si256(texel, _mm256_set1_epi32(0xffff)), _mm256_srli_epi32::<16>(texel));
        // `span` checked the level fits a gather, the one thing `gather_texels` refuses.
        let Some(texel) = gather_texels(texels, size, x, y) else {
            debug_assert!(false, "a level of {size:?} for {} texels was not refused", texels.len());
            continue;
        };
        paint_over!(SRC, color, c, pass, texel, tint);
    }
}

/// The second pass over a block of chunks `(column, pass mask, [columns, rows, weights])` (each pair's first
/// in its low 16 bits, its second in its high 16): each chunk's four texels gathered from `texture`,
/// blended and painted over `color`.
#[inline]
#[target_feature(enable = "avx2")]
fn write_bilinear<const SRC: u8>(
    block: &[(usize, __m256i, [__m256i; 3])],
    texture: &Texture,
    tint: [u32; 3],
    color: &mut [u32],
) {
    let unpack = |p: __m256i| (_mm256_and_si256(p, _mm256_set1_epi32(0xffff)), _mm256_srli_epi32::<16>(p));
    for &(c, pass, [xy, xy1, weights]) in block {
        let ((x, y), (x1, y1)) = (unpack(xy), unpack(xy1));
        let texel = blend_2x2_x8!(texture, (x, x1), (y, y1), unpack(weights));
        paint_over!(SRC, color, c, pass, texel, tint);
    }
}

#[cfg(test)]
thread_local! {
    /// Pixels drawn or rejected depth first on this thread.
    pub(super) static PIXELS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
    /// Chunks whose texels were read from one row on this thread.
    pub(super) static ONE_ROW: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

#[cfg(test)]
#[path = "depth_first_tests.rs"]
mod tests;
