//! Eight pixels of one polygon anywhere in a band shaded at once with AVX2: the colour the chunk loop
//! gives a pixel, from each pixel's own `1/w`, `s/w` and `t/w` instead of a span's steps.
//!
//! The anti-aliased fill draws the pixels an edge crosses (and those another polygon's edge split inside an
//! inner run) one at a time, each with its own samples; their texels are worth shading together, so the
//! fill gathers them from all of a polygon's rows in the band and shades eight at once, a lane each. Each
//! lane is the chunk loop at offset 0 of a span starting at its pixel (`q0 + 0·dq` and so on, operation for
//! operation), so the colour is `colour_at`'s bit for bit.

use crate::render::simd::x86::span::*;

use crate::render::core::mip::{LOG2_QUARTIC, TexGradients};
use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
use crate::render::fill::row::{DROPPED, LANES, TINTED};
use crate::render::fill::texel::Tex;
use crate::render::simd::Avx2;

/// The colours of eight pixels whose depth, `1/w`, `s/w` and `t/w` are `a[l]`, for a texel source `SRC`
/// (the chunk loop's `TEXEL` or `TINTED`) with texture `tex`, tint `tint` and alpha mask `alpha`;
/// [`DROPPED`] where the alpha mask drops a pixel.
pub(crate) fn shade_points<const SRC: u8>(
    _: Avx2,
    a: &[[f32; 4]; LANES],
    tex: Tex<'_>,
    (tint, alpha): ([u32; 3], Option<(f32, f32)>),
) -> [u32; LANES] {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all the body needs.
    #[allow(unsafe_code)]
    unsafe {
        shade_points_avx2::<SRC>(a, tex, (tint, alpha))
    }
}

/// [`shade_points`]'s body, compiled for AVX2.
#[target_feature(enable = "avx2")]
fn shade_points_avx2<const SRC: u8>(
    a: &[[f32; 4]; LANES],
    t: Tex<'_>,
    (tint, alpha): ([u32; 3], Option<(f32, f32)>),
) -> [u32; LANES] {
    let lanes = |i: usize| _mm256_setr_ps(a[0][i], a[1][i], a[2][i], a[3][i], a[4][i], a[5][i], a[6][i], a[7][i]);
    // `coordinates_x8` at offset 0: each attribute plus `0·step`, which turns `-0.0` into `0.0` as it does.
    let nothing = _mm256_mul_ps(_mm256_setzero_ps(), _mm256_setzero_ps());
    let q = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_add_ps(lanes(1), nothing));
    let u = _mm256_mul_ps(_mm256_add_ps(lanes(2), nothing), q);
    let v = _mm256_mul_ps(_mm256_add_ps(lanes(3), nothing), q);
    let pass = _mm256_set1_epi32(-1);
    let texels = match (&t.per_pixel, t.filter) {
        (None, Filter::Nearest) => texels_x8!(u, v, t.texture, t.sampler, false),
        (Some(g), Filter::Nearest) => per_pixel_texels_at_x8!(q, u, v, t, g, pass, false),
        _ => filtered_texels_at_x8!(q, u, v, t, pass, false),
    };
    // Alpha mask: the texel's alpha times the polygon's, kept when at least the cutoff (NaN fails).
    let kept = match alpha {
        Some((a, cutoff)) => {
            let ta = _mm256_cvtepi32_ps(_mm256_srli_epi32::<24>(texels));
            let ta = _mm256_mul_ps(_mm256_mul_ps(ta, _mm256_set1_ps(1.0 / 255.0)), _mm256_set1_ps(a));
            _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(ta, _mm256_set1_ps(cutoff)))
        }
        _ => pass,
    };
    let color = match SRC {
        TINTED => tint_x8!(texels, tint),
        _ => _mm256_and_si256(texels, _mm256_set1_epi32(0x00ff_ffff)),
    };
    bytemuck::cast(_mm256_blendv_epi8(_mm256_set1_epi32(DROPPED as i32), color, kept))
}
