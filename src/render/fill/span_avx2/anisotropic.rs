//! The anisotropic filter on eight pixels with AVX2: each lane's probes measured, counted and placed as
//! [`anisotropic::probes`] does, and the probes' boxes read a probe index at a time for every lane.
//!
//! Operation for operation the scalar rule (the same IEEE operations in the same order; the saturating
//! conversions rebuilt with compares and blends), so a lane's texel is `Tex::probed`'s bit for bit. A
//! probe index whose drawn lanes share a level reads that level on all eight lanes (they mostly do: the
//! level changes slowly along a span); otherwise each lane reads its own box. The mean divides in floats:
//! a sum below 2^16 over at most 16 probes is exact, and its quotient is at least `1/16` from the next
//! integer unless it is one, so truncation gives the integer division's result.

use std::arch::x86_64::{
    __m256, __m256i, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_UNORD_Q, _mm256_add_epi16, _mm256_add_epi32,
    _mm256_add_ps, _mm256_and_ps, _mm256_and_si256, _mm256_andnot_si256, _mm256_blendv_epi8, _mm256_blendv_ps,
    _mm256_castps_si256, _mm256_castsi256_ps, _mm256_ceil_ps, _mm256_cmp_ps, _mm256_cmpeq_epi32, _mm256_cmpgt_epi32,
    _mm256_cvtepi32_ps, _mm256_cvttps_epi32, _mm256_div_ps, _mm256_max_epi32, _mm256_max_ps, _mm256_min_epi32,
    _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps, _mm256_mullo_epi16, _mm256_or_si256, _mm256_set1_epi32,
    _mm256_set1_ps, _mm256_setzero_si256, _mm256_slli_epi32, _mm256_sqrt_ps, _mm256_srli_epi16, _mm256_srli_epi32,
    _mm256_sub_epi32, _mm256_sub_ps,
};

use crate::render::core::anisotropic::box_sample;
use crate::render::core::mip::TexGradients;
use crate::render::core::texture::{Sampler, Texture, Wrap};
use crate::render::fill::row::LANES;
use crate::render::fill::texel::Tex;

/// Each lane's probes, as [`anisotropic::probes`](crate::render::core::anisotropic::probes) gives them.
struct ProbesX8 {
    level: __m256i,
    radius: (__m256, __m256),
    count: __m256i,
    step: (__m256, __m256),
}

/// The anisotropic texels of eight pixels whose `w`, `u` and `v` are given, of `tex`'s mip chain for a
/// polygon with gradients `g`; lanes outside `pass` are not drawn and take one probe.
#[target_feature(enable = "avx2")]
pub(crate) fn probed_x8(
    (q, u, v): (__m256, __m256, __m256),
    tex: &Tex<'_>,
    g: &TexGradients,
    pass: __m256i,
) -> __m256i {
    let (chain, sampler) = (tex.texture, tex.sampler);
    let p = probes_x8(q, (u, v), chain, g, tex.filter.max_probes(), pass);
    let counts: [i32; LANES] = bytemuck::cast(p.count);
    let most = counts.iter().copied().max().unwrap_or(1);
    if most <= 1 {
        // One probe each (a magnified or round footprint): its box is the texel, as `Probes::average` has it.
        return boxes_x8(chain, (u, v), p.radius, p.level, sampler, pass);
    }
    let (mut even, mut odd) = (_mm256_setzero_si256(), _mm256_setzero_si256());
    let m = _mm256_set1_epi32(0x00ff_00ff);
    // `(count - 1) * 0.5`: probe `i` sits `i` minus that steps from the pixel.
    let middle =
        _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(p.count, _mm256_set1_epi32(1))), _mm256_set1_ps(0.5));
    for i in 0..most {
        let active = _mm256_and_si256(pass, _mm256_cmpgt_epi32(p.count, _mm256_set1_epi32(i)));
        let t = _mm256_sub_ps(_mm256_set1_ps(i as f32), middle);
        let pu = _mm256_add_ps(u, _mm256_mul_ps(t, p.step.0));
        let pv = _mm256_add_ps(v, _mm256_mul_ps(t, p.step.1));
        let texel = boxes_x8(chain, (pu, pv), p.radius, p.level, sampler, active);
        let texel = _mm256_and_si256(texel, active);
        even = _mm256_add_epi32(even, _mm256_and_si256(texel, m));
        odd = _mm256_add_epi32(odd, _mm256_and_si256(_mm256_srli_epi32::<8>(texel), m));
    }
    // `(sum + n/2) / n` on each 16-bit field.
    let n = _mm256_cvtepi32_ps(p.count);
    let half = _mm256_srli_epi32::<1>(p.count);
    let field = _mm256_set1_epi32(0xffff);
    let mean = |sum: __m256i| {
        let s = _mm256_cvtepi32_ps(_mm256_add_epi32(sum, half));
        _mm256_cvttps_epi32(_mm256_div_ps(s, n))
    };
    let (b, r) = (mean(_mm256_and_si256(even, field)), mean(_mm256_srli_epi32::<16>(even)));
    let (gr, a) = (mean(_mm256_and_si256(odd, field)), mean(_mm256_srli_epi32::<16>(odd)));
    _mm256_or_si256(
        _mm256_or_si256(b, _mm256_slli_epi32::<8>(gr)),
        _mm256_or_si256(_mm256_slli_epi32::<16>(r), _mm256_slli_epi32::<24>(a)),
    )
}

/// Each lane's probes (lanes outside `pass`, and footprints that cannot be measured: one probe of no size
/// at level 0).
// long: one rule, operation for operation the scalar `probes`; split, its vectors would pass through memory.
#[target_feature(enable = "avx2")]
fn probes_x8(
    w: __m256,
    (u, v): (__m256, __m256),
    chain: &Texture,
    g: &TexGradients,
    max: u8,
    pass: __m256i,
) -> ProbesX8 {
    let (tw, th) = (_mm256_set1_ps(chain.width() as f32), _mm256_set1_ps(chain.height() as f32));
    let side = |d: &[f32; 3]| {
        let d0 = _mm256_set1_ps(d[0]);
        let su = _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(d[1]), _mm256_mul_ps(u, d0)), w), tw);
        let sv = _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(d[2]), _mm256_mul_ps(v, d0)), w), th);
        (su, sv)
    };
    let (x, y) = (side(&g.dx), side(&g.dy));
    let square = |s: (__m256, __m256)| _mm256_add_ps(_mm256_mul_ps(s.0, s.0), _mm256_mul_ps(s.1, s.1));
    let (x2, y2) = (square(x), square(y));
    let ge = _mm256_cmp_ps::<_CMP_GE_OQ>(x2, y2);
    let pick = |a: __m256, b: __m256| _mm256_blendv_ps(b, a, ge);
    let (long, short) = ((pick(x.0, y.0), pick(x.1, y.1)), (pick(y.0, x.0), pick(y.1, x.1)));
    let (major2, minor2) = (pick(x2, y2), pick(y2, x2));
    let inf = _mm256_set1_ps(f32::INFINITY);
    let finite = _mm256_and_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(major2, inf), _mm256_cmp_ps::<_CMP_LT_OQ>(minor2, inf));
    let measured = _mm256_and_si256(pass, _mm256_castps_si256(finite));
    let one = _mm256_set1_ps(1.0);
    let most = _mm256_max_ps(
        _mm256_min_ps(_mm256_set1_ps(f32::from(max.clamp(1, 16))), _mm256_ceil_ps(_mm256_sqrt_ps(major2))),
        one,
    );
    let ratio = _mm256_sqrt_ps(_mm256_div_ps(major2, minor2));
    let count =
        _mm256_min_ps(_mm256_max_ps(_mm256_ceil_ps(_mm256_sub_ps(ratio, _mm256_set1_ps(1.0 / 64.0))), one), most);
    let count = _mm256_blendv_ps(count, one, _mm256_cmp_ps::<_CMP_UNORD_Q>(ratio, ratio));
    let abs = |x: __m256| _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7fff_ffff)));
    let extent = (
        _mm256_add_ps(_mm256_div_ps(abs(long.0), count), abs(short.0)),
        _mm256_add_ps(_mm256_div_ps(abs(long.1), count), abs(short.1)),
    );
    // `level_for`: ⌈log2 e⌉ by the exponent, 0 for at most a texel, at most the last level.
    let e = _mm256_max_ps(extent.0, extent.1);
    let bits = _mm256_castps_si256(e);
    let exponent = _mm256_and_si256(_mm256_srli_epi32::<23>(bits), _mm256_set1_epi32(0xff));
    let whole = _mm256_cmpeq_epi32(_mm256_and_si256(bits, _mm256_set1_epi32(0x007f_ffff)), _mm256_setzero_si256());
    let above = _mm256_andnot_si256(whole, _mm256_set1_epi32(1));
    let level = _mm256_add_epi32(_mm256_sub_epi32(exponent, _mm256_set1_epi32(127)), above);
    let small = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(e, one));
    let level = _mm256_andnot_si256(small, _mm256_min_epi32(level, _mm256_set1_epi32(chain.last_level() as i32)));
    let level = _mm256_max_epi32(level, _mm256_setzero_si256());
    // 1 / 2^level, exactly: the exponent field of 2^-level.
    let scale = _mm256_castsi256_ps(_mm256_slli_epi32::<23>(_mm256_sub_epi32(_mm256_set1_epi32(127), level)));
    let half = _mm256_set1_ps(0.5);
    let radius = |e: __m256| _mm256_min_ps(_mm256_mul_ps(_mm256_mul_ps(e, scale), half), half);
    let step = (_mm256_div_ps(long.0, _mm256_mul_ps(tw, count)), _mm256_div_ps(long.1, _mm256_mul_ps(th, count)));
    let keep = |x: __m256| _mm256_and_ps(x, _mm256_castsi256_ps(measured));
    ProbesX8 {
        level: _mm256_and_si256(level, measured),
        radius: (keep(radius(extent.0)), keep(radius(extent.1))),
        count: _mm256_blendv_epi8(_mm256_set1_epi32(1), _mm256_cvttps_epi32(count), measured),
        step: (keep(step.0), keep(step.1)),
    }
}

/// The box of each active lane (`active`) at its probe `(pu, pv)`, of half-size `radius` in texels of its
/// level: all eight lanes from one level when the active lanes share it, else one lane at a time.
#[target_feature(enable = "avx2")]
fn boxes_x8(
    chain: &Texture,
    uv: (__m256, __m256),
    radius: (__m256, __m256),
    level: __m256i,
    sampler: Sampler,
    active: __m256i,
) -> __m256i {
    if let Some(k) = shared_level!(level, active)
        && let Some(texels) = box_x8(chain.level(k), uv, radius, sampler)
    {
        return texels;
    }
    let (us, vs): ([f32; LANES], [f32; LANES]) = (bytemuck::cast(uv.0), bytemuck::cast(uv.1));
    let (rx, ry): ([f32; LANES], [f32; LANES]) = (bytemuck::cast(radius.0), bytemuck::cast(radius.1));
    let (levels, on): ([i32; LANES], [i32; LANES]) = (bytemuck::cast(level), bytemuck::cast(active));
    let out: [u32; LANES] = std::array::from_fn(|l| {
        let texture = chain.level(levels[l].max(0) as usize);
        if on[l] == 0 { 0 } else { box_sample(texture, (us[l], vs[l]), [rx[l], ry[l]], sampler) }
    });
    bytemuck::cast(out)
}

/// `box_sample` on eight lanes of one level; `None` for wrap modes drawn per lane.
#[target_feature(enable = "avx2")]
fn box_x8(
    texture: &Texture,
    (u, v): (__m256, __m256),
    (rx, ry): (__m256, __m256),
    sampler: Sampler,
) -> Option<__m256i> {
    let (w, h) = (texture.width(), texture.height());
    let one = _mm256_set1_ps(1.0);
    // `box_axis`: the first texel the box meets and the share of the box past it, in 1/256.
    let axis = |c: __m256, r: __m256| {
        let first = floor_i32x8!(_mm256_sub_ps(c, r));
        let over = _mm256_sub_ps(_mm256_add_ps(c, r), _mm256_add_ps(_mm256_cvtepi32_ps(first), one));
        let share = _mm256_min_ps(_mm256_div_ps(over, _mm256_add_ps(r, r)), one);
        let share =
            _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(share, _mm256_set1_ps(256.0)), _mm256_set1_ps(0.5)));
        let past = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(over, _mm256_set1_ps(0.0)));
        (first, _mm256_and_si256(share, past))
    };
    let (x, ax) = axis(_mm256_mul_ps(u, _mm256_set1_ps(w as f32)), rx);
    let (y, ay) = axis(_mm256_mul_ps(v, _mm256_set1_ps(h as f32)), ry);
    let next = |i: __m256i| _mm256_add_epi32(i, _mm256_set1_epi32(1));
    let (x, x1) = wrap_x8!(x, w, sampler.wrap_s).zip(wrap_x8!(next(x), w, sampler.wrap_s))?;
    let (y, y1) = wrap_x8!(y, h, sampler.wrap_t).zip(wrap_x8!(next(y), h, sampler.wrap_t))?;
    Some(blend_2x2_x8!(texture, (x, x1), (y, y1), (ax, ay)))
}
