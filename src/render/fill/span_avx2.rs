//! The span fast paths' chunks with AVX2: eight pixels per instruction, written out by hand because
//! the compiler keeps the saturating float-to-integer conversions scalar.
//!
//! Each step repeats the portable loop in [`crate::render::fill::span_lanes`] operation for operation (the same IEEE
//! operations in the same order, no fused multiply-add; `floor_i32`'s saturation and NaN rule are rebuilt
//! with compares and blends), so the two produce bit-identical frames; a unit test compares them on
//! random and hostile spans. The texels follow [`crate::render::fill::texel`]'s reference: nearest, or
//! bilinear and trilinear blended in integers (two channels per 16-bit pair of lanes); a mip level chosen
//! per pixel is measured on all eight lanes too, and the texels fetched from one level at once when the
//! drawn lanes share it.

use crate::render::simd::x86::span::*;

use super::row::{COVERAGE, DEPTH_TEST, FLAT, LANES, PackedCounts, Row, Setup, TINTED, cover_bits, coverage_byte};
use super::texel::Tex;
use crate::render::core::mip::{LOG2_QUARTIC, TexGradients};
use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::simd::Avx2;
use crate::render::simd::x86::{load8, store8};

// The helpers are macros rather than functions: a `#[target_feature]` function cannot be `inline(always)`,
// and the compiler leaves them as calls, passing every vector through memory.

/// `floor_i32` on eight lanes: truncation corrected downwards, NaN to 0, saturating at both ends.
macro_rules! floor_i32x8 {
    ($f:expr) => {{
        let f: __m256 = $f;
        let i = _mm256_cvttps_epi32(f);
        // -1 where truncation went up (negative non-integers), added to step down.
        let down = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(f, _mm256_cvtepi32_ps(i)));
        let i = _mm256_add_epi32(i, down);
        // The conversion gives i32::MIN for NaN and out of range; `as i32` gives 0, MAX and MIN.
        let too_big = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(f, _mm256_set1_ps(2_147_483_648.0)));
        let too_small = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(f, _mm256_set1_ps(-2_147_483_648.0)));
        let nan = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_UNORD_Q>(f, f));
        let i = _mm256_blendv_epi8(i, _mm256_set1_epi32(i32::MAX), too_big);
        let i = _mm256_blendv_epi8(i, _mm256_set1_epi32(i32::MIN), too_small);
        _mm256_andnot_si256(nan, i)
    }};
}

/// `floor_i32` on eight lanes whose values are known finite and within `±2^30`: the truncation corrected
/// downwards, without the saturation and NaN fix-ups (which would change nothing).
macro_rules! floor_in_range_x8 {
    ($f:expr) => {{
        let f: __m256 = $f;
        let i = _mm256_cvttps_epi32(f);
        _mm256_add_epi32(i, _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(f, _mm256_cvtepi32_ps(i))))
    }};
}

/// Texel coordinates folded into `0..size` on eight lanes, or `None` for wrap modes drawn per lane.
macro_rules! wrap_x8 {
    ($i:expr, $size:expr, $mode:expr) => {{
        let (i, size): (__m256i, u32) = ($i, $size);
        match $mode {
            Wrap::Repeat if size.is_power_of_two() => Some(_mm256_and_si256(i, _mm256_set1_epi32((size - 1) as i32))),
            Wrap::ClampToEdge => {
                let hi = _mm256_set1_epi32(size.saturating_sub(1).min(i32::MAX as u32) as i32);
                Some(_mm256_min_epi32(_mm256_max_epi32(i, _mm256_setzero_si256()), hi))
            }
            _ => None,
        }
    }};
}

/// `w` (the reciprocal of the interpolated `1/w`) and the texture coordinates `u`, `v` of eight pixels at
/// offsets `k`.
macro_rules! coordinates_x8 {
    ($s:expr, $k:expr) => {{
        let (s, k): (&Setup, __m256) = ($s, $k);
        let q = _mm256_add_ps(_mm256_set1_ps(s.q0), _mm256_mul_ps(k, _mm256_set1_ps(s.dq)));
        let q = _mm256_div_ps(_mm256_set1_ps(1.0), q);
        let u = _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(s.s0), _mm256_mul_ps(k, _mm256_set1_ps(s.ds))), q);
        let v = _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(s.t0), _mm256_mul_ps(k, _mm256_set1_ps(s.dt))), q);
        (q, u, v)
    }};
}

/// The nearest texels' indices and texels on eight lanes.
#[macro_use]
mod nearest;

/// The mip level nearest the level of detail at eight pixels, as `Tex::texel_at` chooses it for one:
/// `TexGradients::lod_at`, `lod_from_squares` (with `f32::max`'s NaN rule and `log2_approx`'s quartic)
/// and `nearest_level`, operation for operation. `q` is `w` (the reciprocal of `1/w`, as
/// [`coordinates_x8`] gives it), `u`, `v` the texture coordinates, `size` level 0's.
macro_rules! lod_x8 {
    ($q:expr, $u:expr, $v:expr, $g:expr, $size:expr) => {{
        let (q, u, v, g, (tw, th)): (__m256, __m256, __m256, &TexGradients, (u32, u32)) = ($q, $u, $v, $g, $size);
        let (tw, th) = (_mm256_mul_ps(_mm256_set1_ps(tw as f32), q), _mm256_mul_ps(_mm256_set1_ps(th as f32), q));
        let square = |d: &[f32; 3]| {
            let d0 = _mm256_set1_ps(d[0]);
            let du = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(d[1]), _mm256_mul_ps(u, d0)), tw);
            let dv = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(d[2]), _mm256_mul_ps(v, d0)), th);
            _mm256_add_ps(_mm256_mul_ps(du, du), _mm256_mul_ps(dv, dv))
        };
        let (x2, y2) = (square(&g.dx), square(&g.dy));
        // `f32::max` returns the other operand when one is NaN; `maxps` returns its second.
        let rho2 = _mm256_blendv_ps(_mm256_max_ps(x2, y2), x2, _mm256_cmp_ps::<_CMP_UNORD_Q>(y2, y2));
        let usable = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(rho2, _mm256_setzero_ps()),
            _mm256_cmp_ps::<_CMP_LT_OQ>(rho2, _mm256_set1_ps(f32::INFINITY)),
        );
        let bits = _mm256_castps_si256(rho2);
        let exponent = _mm256_sub_epi32(
            _mm256_and_si256(_mm256_srli_epi32::<23>(bits), _mm256_set1_epi32(0xff)),
            _mm256_set1_epi32(127),
        );
        let m = _mm256_castsi256_ps(_mm256_or_si256(
            _mm256_and_si256(bits, _mm256_set1_epi32(0x007f_ffff)),
            _mm256_set1_epi32(0x3f80_0000),
        ));
        let m = _mm256_sub_ps(m, _mm256_set1_ps(1.0));
        let c = |i: usize| _mm256_set1_ps(LOG2_QUARTIC[i]);
        let p = _mm256_add_ps(c(2), _mm256_mul_ps(m, c(3)));
        let p = _mm256_add_ps(c(1), _mm256_mul_ps(m, p));
        let p = _mm256_add_ps(c(0), _mm256_mul_ps(m, p));
        let log2 = _mm256_add_ps(_mm256_cvtepi32_ps(exponent), _mm256_mul_ps(m, p));
        _mm256_and_ps(usable, _mm256_mul_ps(_mm256_set1_ps(0.5), log2))
    }};
}

/// `nearest_level` on eight lanes of `λ` from [`lod_x8`] (finite, within ±64.5).
macro_rules! nearest_x8 {
    ($lod:expr, $last:expr) => {{
        let (lod, last): (__m256, usize) = ($lod, $last);
        // `(lod + 0.5) as usize`: negatives to 0 (the sum is finite, at most 64.5, so truncation is exact).
        let nearest = _mm256_max_ps(_mm256_add_ps(lod, _mm256_set1_ps(0.5)), _mm256_setzero_ps());
        _mm256_min_epi32(_mm256_cvttps_epi32(nearest), _mm256_set1_epi32(last.min(255) as i32))
    }};
}

/// `trilinear_levels` on eight lanes of `λ` from [`lod_x8`]: the finer level and the coarser one's weight.
macro_rules! trilinear_x8 {
    ($lod:expr, $last:expr) => {{
        let (lod, last): (__m256, usize) = ($lod, $last);
        let last = _mm256_set1_epi32(last.min(255) as i32);
        let k = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_max_ps(lod, _mm256_setzero_ps())), last);
        let f = _mm256_mul_ps(_mm256_sub_ps(lod, _mm256_cvtepi32_ps(k)), _mm256_set1_ps(256.0));
        // `as u32` sends negatives to 0; the weight is 0 at the last level.
        let weight =
            _mm256_min_epi32(_mm256_max_epi32(_mm256_cvttps_epi32(f), _mm256_setzero_si256()), _mm256_set1_epi32(255));
        (k, _mm256_andnot_si256(_mm256_cmpeq_epi32(k, last), weight))
    }};
}

/// `blend` on eight lanes: texels `x` and `y` per channel with weights `a` (0..=256) on `y`, rounded.
macro_rules! blend_x8 {
    ($x:expr, $y:expr, $a:expr) => {{
        let (x, y, a): (__m256i, __m256i, __m256i) = ($x, $y, $a);
        let m = _mm256_set1_epi32(0x00ff_00ff);
        let half = _mm256_set1_epi32(0x0080_0080);
        let pair = |w: __m256i| _mm256_or_si256(w, _mm256_slli_epi32::<16>(w));
        let (a, b) = (pair(a), pair(_mm256_sub_epi32(_mm256_set1_epi32(256), a)));
        let mix = |x: __m256i, y: __m256i| {
            _mm256_add_epi16(_mm256_add_epi16(_mm256_mullo_epi16(x, b), _mm256_mullo_epi16(y, a)), half)
        };
        let rb = _mm256_srli_epi16::<8>(mix(_mm256_and_si256(x, m), _mm256_and_si256(y, m)));
        let ag = mix(_mm256_and_si256(_mm256_srli_epi32::<8>(x), m), _mm256_and_si256(_mm256_srli_epi32::<8>(y), m));
        _mm256_or_si256(rb, _mm256_andnot_si256(m, ag))
    }};
}

/// `area_weight` on eight lanes: bilinear weights `a` (0..=255) sharpened to a box footprint `extent`
/// texels long, by the same operations (`maxps` gives its second operand, 1/64, for NaN, as `f32::max`).
macro_rules! area_weight_x8 {
    ($a:expr, $extent:expr) => {{
        let (a, e): (__m256i, __m256) = ($a, $extent);
        let e = _mm256_min_ps(
            _mm256_max_ps(e, _mm256_set1_ps(crate::render::core::texture::AREA_MIN_EXTENT)),
            _mm256_set1_ps(1.0),
        );
        let f = _mm256_div_ps(_mm256_sub_ps(_mm256_cvtepi32_ps(a), _mm256_set1_ps(128.0)), e);
        let f = _mm256_min_ps(
            _mm256_max_ps(_mm256_add_ps(f, _mm256_set1_ps(128.5)), _mm256_setzero_ps()),
            _mm256_set1_ps(256.0),
        );
        _mm256_cvttps_epi32(f)
    }};
}

/// `TexGradients::extent_at` on eight lanes: the footprint's extent in texels across and down at pixels
/// whose `w`, `u`, `v` are given (as [`coordinates_x8`] gives them), for level 0 of `size` texels.
macro_rules! extent_x8 {
    ($q:expr, $u:expr, $v:expr, $g:expr, $size:expr) => {{
        let (q, u, v, g, (tw, th)): (__m256, __m256, __m256, &TexGradients, (u32, u32)) = ($q, $u, $v, $g, $size);
        let abs = |x: __m256| _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fff_ffff)));
        let d = |c: __m256, d: &[f32; 3], i: usize| {
            abs(_mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(d[i]), _mm256_mul_ps(c, _mm256_set1_ps(d[0]))), q))
        };
        let across = _mm256_mul_ps(_mm256_add_ps(d(u, &g.dx, 1), d(u, &g.dy, 1)), _mm256_set1_ps(tw as f32));
        let down = _mm256_mul_ps(_mm256_add_ps(d(v, &g.dx, 2), d(v, &g.dy, 2)), _mm256_set1_ps(th as f32));
        (across, down)
    }};
}

/// Bilinear texels on eight lanes: the corners and weights, the 2x2 blend, the texels.
#[macro_use]
mod bilinear;

/// The level every drawn lane (`pass`) of `levels` shares, if they share one (they mostly do: the level
/// changes slowly along a span).
macro_rules! shared_level {
    ($levels:expr, $pass:expr) => {{
        let (levels, pass): (__m256i, __m256i) = ($levels, $pass);
        let drawn = _mm256_movemask_ps(_mm256_castsi256_ps(pass)) as u32;
        let first: [i32; LANES] = bytemuck::cast(levels);
        let first = first[drawn.trailing_zeros() as usize % LANES];
        let same = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(levels, _mm256_set1_epi32(first))));
        (drawn & !(same as u32) == 0).then_some(first as usize)
    }};
}

/// The texels of eight lanes one at a time (`Tex::at_lod` on each lane's `u`, `v` and `λ`), for lanes
/// whose levels differ.
macro_rules! lane_by_lane {
    ($tex:expr, $u:expr, $v:expr, $lod:expr) => {{
        let (us, vs, lods): ([f32; LANES], [f32; LANES], [f32; LANES]) =
            (bytemuck::cast($u), bytemuck::cast($v), bytemuck::cast($lod));
        let out: [u32; LANES] = std::array::from_fn(|l| $tex.at_lod(us[l], vs[l], lods[l]));
        bytemuck::cast::<[u32; LANES], __m256i>(out)
    }};
}

/// The bilinear or trilinear texels of eight pixels at offsets `k` (`Tex::texel_at`): from the polygon's
/// level (or two), or from the levels chosen at each pixel, fetched a level at a time when the drawn lanes
/// (`pass`) share it, else one lane at a time.
macro_rules! filtered_texels_x8 {
    ($s:expr, $k:expr, $tex:expr, $pass:expr, $in_range:expr) => {{
        let (s, k): (&Setup, __m256) = ($s, $k);
        let (q, u, v) = coordinates_x8!(s, k);
        filtered_texels_at_x8!(q, u, v, $tex, $pass, $in_range)
    }};
}

/// [`filtered_texels_x8`] at pixels whose `w`, `u` and `v` are given (as [`coordinates_x8`] gives them).
macro_rules! filtered_texels_at_x8 {
    ($q:expr, $u:expr, $v:expr, $tex:expr, $pass:expr, $in_range:expr) => {{
        let (q, u, v, tex, pass): (__m256, __m256, __m256, Tex<'_>, __m256i) = ($q, $u, $v, $tex, $pass);
        let t = tex.texture;
        match &tex.per_pixel {
            None => {
                let fine = bilinear_x8!(u, v, t, tex.sampler, $in_range);
                match tex.coarser {
                    Some((c, w)) => {
                        blend_x8!(fine, bilinear_x8!(u, v, c, tex.sampler, $in_range), _mm256_set1_epi32(w as i32))
                    }
                    None => fine,
                }
            }
            Some(g) if tex.filter == Filter::Area => {
                let extent = extent_x8!(q, u, v, g, (t.width(), t.height()));
                bilinear_x8!(u, v, t, tex.sampler, $in_range, Some(extent))
            }
            Some(g) if matches!(tex.filter, Filter::Anisotropic(_)) => {
                crate::render::fill::span_avx2::anisotropic::probed_x8((q, u, v), &tex, g, pass)
            }
            Some(g) => {
                let lod = lod_x8!(q, u, v, g, (t.width(), t.height()));
                let last = t.last_level();
                let (levels, weight) = match tex.filter {
                    Filter::Trilinear | Filter::Anisotropic(_) => trilinear_x8!(lod, last),
                    _ => (nearest_x8!(lod, last), _mm256_setzero_si256()),
                };
                match shared_level!(levels, pass) {
                    Some(k) => {
                        let fine = bilinear_x8!(u, v, t.level(k), tex.sampler, $in_range);
                        let blends = _mm256_cmpgt_epi32(weight, _mm256_setzero_si256());
                        if _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_and_si256(pass, blends))) == 0 {
                            fine
                        } else {
                            blend_x8!(fine, bilinear_x8!(u, v, t.level(k + 1), tex.sampler, $in_range), weight)
                        }
                    }
                    None => lane_by_lane!(tex, u, v, lod),
                }
            }
        }
    }};
}

/// The nearest texels of eight pixels at offsets `k`, each from the mip level chosen at it: one vector
/// fetch when the drawn lanes (`pass`) share a level (they mostly do: the level changes slowly along a
/// span), else one lane at a time.
macro_rules! per_pixel_texels_x8 {
    ($s:expr, $k:expr, $tex:expr, $g:expr, $pass:expr, $in_range:expr) => {{
        let (s, k): (&Setup, __m256) = ($s, $k);
        let (q, u, v) = coordinates_x8!(s, k);
        per_pixel_texels_at_x8!(q, u, v, $tex, $g, $pass, $in_range)
    }};
}

/// [`per_pixel_texels_x8`] at pixels whose `w`, `u` and `v` are given (as [`coordinates_x8`] gives them).
macro_rules! per_pixel_texels_at_x8 {
    ($q:expr, $u:expr, $v:expr, $tex:expr, $g:expr, $pass:expr, $in_range:expr) => {{
        let (q, u, v, tex, g, pass): (__m256, __m256, __m256, Tex<'_>, &TexGradients, __m256i) =
            ($q, $u, $v, $tex, $g, $pass);
        let t = tex.texture;
        let lod = lod_x8!(q, u, v, g, (t.width(), t.height()));
        match shared_level!(nearest_x8!(lod, t.last_level()), pass) {
            Some(k) => texels_x8!(u, v, t.level(k), tex.sampler, $in_range),
            None => lane_by_lane!(tex, u, v, lod),
        }
    }};
}

/// Multiplies the channels of packed texels by `Fx16` colours and rounds, as the portable tinted path does.
macro_rules! tint_x8 {
    ($t:expr, $tint:expr) => {{
        let (t, [cr, cg, cb]): (__m256i, [u32; 3]) = ($t, $tint);
        let byte = _mm256_set1_epi32(0xff);
        let half = _mm256_set1_epi32(32768);
        let r = _mm256_and_si256(_mm256_srli_epi32::<16>(t), byte);
        let g = _mm256_and_si256(_mm256_srli_epi32::<8>(t), byte);
        let b = _mm256_and_si256(t, byte);
        let r = _mm256_srli_epi32::<16>(_mm256_add_epi32(_mm256_mullo_epi32(r, _mm256_set1_epi32(cr as i32)), half));
        let g = _mm256_srli_epi32::<16>(_mm256_add_epi32(_mm256_mullo_epi32(g, _mm256_set1_epi32(cg as i32)), half));
        let b = _mm256_srli_epi32::<16>(_mm256_add_epi32(_mm256_mullo_epi32(b, _mm256_set1_epi32(cb as i32)), half));
        _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32::<16>(r), _mm256_slli_epi32::<8>(g)), b)
    }};
}

/// One chunk of eight pixels, the body of both chunk loops.
#[macro_use]
mod chunk;
use chunk::{ChunkPixels, ChunkSpan};

/// Draws span pixels `from..x1` (the span's attributes counted from `x0`) eight at a time and returns where
/// it stopped (`x1` unless the row is shorter than a chunk) and its counts. The last chunk is moved back to
/// end inside the row where it would pass the row's end, and lanes outside the span (or already drawn) are
/// masked off. `VIS` and `SRC` are the portable
/// loop's visibility and source codes; `alpha` is the polygon's alpha and the mask cutoff for MASK;
/// `in_range` says the caller has found the span's texel coordinates in range (else the loop checks).
pub(crate) fn chunks<const VIS: u8, const SRC: u8>(
    _: Avx2,
    span: (usize, usize, usize),
    s: &Setup,
    tex: Option<&Tex<'_>>,
    colors: &(u32, [u32; 3], Option<(f32, f32)>),
    row: &mut Row<'_>,
    in_range: bool,
) -> (usize, PackedCounts) {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all `chunks_avx2` needs.
    #[allow(unsafe_code)]
    unsafe {
        chunks_avx2::<VIS, SRC>(span, s, tex, colors, row, in_range)
    }
}

/// [`chunks`]'s body, compiled for AVX2: the span's set-up stays in registers from chunk to chunk.
#[target_feature(enable = "avx2")]
fn chunks_avx2<const VIS: u8, const SRC: u8>(
    (x0, from, x1): (usize, usize, usize),
    s: &Setup,
    tex: Option<&Tex<'_>>,
    &(flat, tint, alpha): &(u32, [u32; 3], Option<(f32, f32)>),
    row: &mut Row<'_>,
    known_in_range: bool,
) -> (usize, PackedCounts) {
    let mut counts = PackedCounts::default();
    let width = row.color.len();
    let in_range = SRC != FLAT && (known_in_range || s.texels_in_range(x1.saturating_sub(x0 + 1)));
    let mut x = from;
    // A span passing the row's end (never one from the fill) stops at it: the last chunk would otherwise
    // be moved back to end inside the row again and again.
    let end = x1.min(width);
    // Spans are clipped to the row by the fill, so the counts fit their 21 bits.
    debug_assert!(end.saturating_sub(x0) < 1 << PackedCounts::BITS, "a span of {} pixels", end - x0);
    if let Some(done) = depth_first::span::<VIS, SRC>((x0, from, x1), (s, in_range), tex, (tint, alpha), row) {
        return done;
    }
    // A row narrower than a chunk is left to the per-pixel loop.
    'span: while x < end && width >= LANES {
        let span = ChunkSpan { x0, x1, s, in_range };
        let pixels = ChunkPixels { color: &mut *row.color, depth: &mut *row.depth, base: 0, width };
        chunk_x8!('span, VIS, SRC, &mut x, span, (tex, flat, tint, alpha), pixels, &mut *row.coverage, &mut counts);
    }
    (x.min(x1), counts)
}

/// Long spans of nearest or bilinear texels behind a depth test, depth first.
mod depth_first;
/// Eight pixels from anywhere in a band shaded by the macros above.
pub(crate) mod points;

/// The anisotropic filter's texels on eight lanes.
mod anisotropic;
/// A polygon's spans of a band in one loop.
pub(crate) mod rows;
