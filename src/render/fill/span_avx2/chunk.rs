//! One chunk of eight pixels of a span, the body shared by the two chunk loops: `chunks_avx2` (one span,
//! its set-up held in registers from chunk to chunk) and [`rows`](super::rows) (a polygon's short spans of
//! a band, one chunk after another across rows).
//!
//! A macro rather than a function: a `#[target_feature]` function cannot be `inline(always)`, and as a
//! call the chunk's vectors would pass through memory.

use crate::render::fill::row::Setup;

/// The span a chunk belongs to: its pixels `x0..x1`, its set-up, and whether its texel coordinates stay in
/// range ([`Setup::texels_in_range`]).
#[derive(Clone, Copy)]
pub(crate) struct ChunkSpan<'s> {
    pub(crate) x0: usize,
    pub(crate) x1: usize,
    pub(crate) s: &'s Setup,
    pub(crate) in_range: bool,
}

/// Where a chunk's row is: colour and depth buffers (a row, or a band), the row's `width` pixels starting
/// at `base` in them.
pub(crate) struct ChunkPixels<'a> {
    pub(crate) color: &'a mut [u32],
    pub(crate) depth: &'a mut [f32],
    pub(crate) base: usize,
    pub(crate) width: usize,
}

// long: one AVX2 chunk; split into functions its vectors would pass through memory.
/// Draws the chunk of span `$span` at `*$x` (a row at least a chunk wide: the chunk is moved back to end
/// inside the row where it would pass the row's end, lanes outside the span or already drawn masked off),
/// adds its counts to `$counts` and moves `*$x` past it; where the row's buffers are too short for the
/// chunk (no caller's are) it leaves `*$x` and breaks out of the loop labelled `$stop`, so that the caller's
/// per-pixel loop draws the rest. `$vis` and `$src` are the portable loop's
/// visibility and source codes, `$paint` the texture and `(flat colour, tint, alpha mask)`, `$coverage`
/// the row's coverage words.
macro_rules! chunk_x8 {
    ($stop:lifetime, $vis:expr, $src:expr, $x:expr, $span:expr, $paint:expr, $pixels:expr, $coverage:expr, $counts:expr) => {{
        let (x, ChunkSpan { x0, x1, s, in_range }, counts): (&mut usize, ChunkSpan<'_>, &mut PackedCounts) =
            ($x, $span, $counts);
        let (tex, flat, tint, alpha): (Option<&Tex<'_>>, u32, [u32; 3], Option<(f32, f32)>) = $paint;
        let ChunkPixels { color: colors, depth: depths, base, width } = $pixels;
        let coverage: &mut [u64] = $coverage;
        debug_assert!(width >= LANES, "a row of {width} pixels");
        'chunk: {
            // `bucket-near`: skip the rest of a coverage word at once when all of it is drawn (on deep scenes
            // most of a late polygon's pixels are).
            if $vis == COVERAGE {
                let (word, bit) = (*x >> 6, *x & 63);
                if coverage.get(word).is_some_and(|&w| w >> bit == u64::MAX >> bit) {
                    let next = ((word + 1) << 6).min(x1);
                    counts.add(0, 0, (next - *x) as u64);
                    *x = next;
                    break 'chunk;
                }
            }
            let c = if *x + LANES <= width { *x } else { width - LANES };
            let lane = _mm256_add_epi32(_mm256_set1_epi32(c as i32), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
            // Lanes in `x..x1`: `lane > x - 1` and `x1 > lane` (pixel indices are below 2^20).
            let valid = _mm256_and_si256(
                _mm256_cmpgt_epi32(lane, _mm256_set1_epi32(*x as i32 - 1)),
                _mm256_cmpgt_epi32(_mm256_set1_epi32(x1 as i32), lane),
            );
            let Some(old_color) = colors.get(base + c..).and_then(load8::<u32, __m256i>) else { break $stop };
            let k = _mm256_cvtepi32_ps(_mm256_sub_epi32(lane, _mm256_set1_epi32(x0 as i32)));
            let depth = _mm256_add_ps(_mm256_set1_ps(s.d0), _mm256_mul_ps(k, _mm256_set1_ps(s.dd)));
            let mut old_depth = depth;
            let visible = match $vis {
                DEPTH_TEST => {
                    let Some(old) = depths.get(base + c..).and_then(load8::<f32, __m256>) else { break $stop };
                    old_depth = old;
                    // Strictly nearer wins, so on equal depth the polygon drawn first stays (like GL_LESS).
                    _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(depth, old))
                }
                COVERAGE => {
                    let bits = _mm256_set1_epi32(i32::from(coverage_byte(coverage, c)));
                    let lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
                    _mm256_cmpeq_epi32(_mm256_and_si256(bits, lane_bits), _mm256_setzero_si256())
                }
                _ => valid,
            };
            *x = c + LANES;
            let pass = _mm256_and_si256(visible, valid);
            let lanes = |m: __m256i| u64::from((_mm256_movemask_ps(bytemuck::cast(m)) as u32).count_ones());
            let n = lanes(pass);
            let rejected = lanes(valid) - n;
            if n == 0 {
                counts.add(0, 0, rejected);
                break 'chunk;
            }
            let texels = match ($src, tex) {
                (FLAT, _) | (_, None) => _mm256_set1_epi32(flat as i32),
                (_, Some(t)) => match (&t.per_pixel, t.filter) {
                    (None, Filter::Nearest) => {
                        let (_, u, v) = coordinates_x8!(s, k);
                        texels_x8!(u, v, t.texture, t.sampler, in_range)
                    }
                    (Some(g), Filter::Nearest) => per_pixel_texels_x8!(s, k, *t, g, pass, in_range),
                    _ => filtered_texels_x8!(s, k, *t, pass, in_range),
                },
            };
            // Alpha mask: the texel's alpha times the polygon's, kept when at least the cutoff (NaN fails).
            let write = match alpha {
                Some((a, cutoff)) if $src != FLAT => {
                    let ta = _mm256_cvtepi32_ps(_mm256_srli_epi32::<24>(texels));
                    let ta = _mm256_mul_ps(_mm256_mul_ps(ta, _mm256_set1_ps(1.0 / 255.0)), _mm256_set1_ps(a));
                    let keep = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(ta, _mm256_set1_ps(cutoff)));
                    _mm256_and_si256(pass, keep)
                }
                _ => pass,
            };
            counts.add(n, lanes(write), rejected);
            let color = match $src {
                FLAT => texels,
                TINTED => tint_x8!(texels, tint),
                _ => _mm256_and_si256(texels, _mm256_set1_epi32(0x00ff_ffff)),
            };
            if let Some(out) = colors.get_mut(base + c..) {
                store8(out, _mm256_blendv_epi8(old_color, color, write));
            }
            match $vis {
                DEPTH_TEST => {
                    if let Some(d) = depths.get_mut(base + c..) {
                        store8(d, _mm256_blendv_ps(old_depth, depth, bytemuck::cast(write)));
                    }
                }
                COVERAGE => cover_bits(coverage, c, _mm256_movemask_ps(bytemuck::cast(write)) as u8),
                _ => {}
            }
        }
    }};
}
