//! The vertex transform eight vertices at a time with AVX2, written out by hand because the compiler keeps
//! the clip codes, the snapping and the record assembly scalar.
//!
//! Each step repeats [`crate::render::geometry::vertex::VertexTransform::vertex`] operation for operation (the
//! same IEEE operations in the same order, no fused multiply-add; `Fx28_4::from_f32`'s rounding and range
//! checks are rebuilt with compares), so the records are bit-identical to the one-vertex loop's.

use std::arch::x86_64::{
    __m128, __m256, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _mm256_add_epi32, _mm256_add_ps,
    _mm256_and_ps, _mm256_and_si256, _mm256_castps_si256, _mm256_castps256_ps128, _mm256_castsi256_ps, _mm256_cmp_ps,
    _mm256_cvtepi32_ps, _mm256_cvttps_epi32, _mm256_div_ps, _mm256_extractf128_ps, _mm256_mul_ps, _mm256_or_si256,
    _mm256_set1_epi32, _mm256_set1_ps, _mm256_shuffle_ps, _mm256_slli_epi32, _mm256_sub_epi32, _mm256_sub_ps,
    _mm256_unpackhi_ps, _mm256_unpacklo_ps, _mm256_xor_ps,
};

use super::vertex::{SetupVertex, VertexTransform};
use crate::render::core::fixed::Fx28_4;
use crate::render::core::mesh::Vertex;
use crate::render::simd::Avx2;

/// Vertices per step.
const LANES: usize = 8;

/// Transforms `vs` into `out` (as many as the shorter holds) and returns how many it did: all of them, the
/// last few (fewer than eight) as a group padded with vertices at the origin whose records are dropped.
/// The padded group is worth it: a mountain frame draws thousands of trees and rocks of a few vertices
/// each, and one at a time their vertices took as long as all the groups of eight.
pub(crate) fn run(_: Avx2, t: &VertexTransform, out: &mut [SetupVertex], vs: &[Vertex]) -> usize {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all `run_avx2` needs.
    #[allow(unsafe_code)]
    unsafe {
        run_avx2(t, out, vs)
    }
}

// long: one AVX2 loop body; split into functions its vectors would pass through memory (a `#[target_feature]` function cannot be `inline(always)`).
/// [`run`]'s body, compiled for AVX2.
#[target_feature(enable = "avx2")]
fn run_avx2(t: &VertexTransform, out: &mut [SetupVertex], vs: &[Vertex]) -> usize {
    let all = out.len().min(vs.len());
    let n = all / LANES * LANES;
    // The last group, padded: its records are written here and copied out after the loop.
    let origin = Vertex::new(glam::Vec3::ZERO, glam::Vec2::ZERO);
    let mut last_in = [origin; LANES];
    let mut last_out = [SetupVertex::default(); LANES];
    let rest = all - n;
    if let (Some(to), Some(from)) = (last_in.get_mut(..rest), vs.get(n..all)) {
        to.copy_from_slice(from);
    }
    let padded = (rest > 0).then_some((&mut last_out[..], &last_in[..]));
    let m = &t.clip_from_model;
    let d = t.depth_row;
    let s = _mm256_set1_ps;
    let (gx, gy) = (s(t.volume.guard_x), s(t.volume.guard_y));
    let far = t.volume.far;
    let sign = s(-0.0);
    let abs = |v: __m256| _mm256_and_ps(v, s(f32::from_bits(0x7fff_ffff)));
    let finite = |v: __m256| _mm256_cmp_ps::<_CMP_LT_OQ>(abs(v), s(f32::INFINITY));
    // The mask of lanes where `c` holds, as bit `shift` of each lane.
    let bit = |c: __m256, shift: i32| _mm256_and_si256(_mm256_castps_si256(c), _mm256_set1_epi32(1 << shift));
    // `Fx28_4::from_f32`: the raw value and the lanes where it exists.
    let snap = |v: __m256| {
        let ok = _mm256_and_ps(finite(v), _mm256_cmp_ps::<_CMP_LE_OQ>(abs(v), s(Fx28_4::MAX_PIXELS)));
        let scaled = _mm256_mul_ps(v, s(Fx28_4::ONE as f32));
        let t = _mm256_cvttps_epi32(scaled);
        let frac = _mm256_sub_ps(scaled, _mm256_cvtepi32_ps(t));
        // Compare masks are -1 where true: subtracting the first adds one, adding the second takes one away.
        let up = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(frac, s(0.5)));
        let down = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(frac, s(-0.5)));
        (_mm256_add_epi32(_mm256_sub_epi32(t, up), down), ok)
    };
    for (outs, ins) in out[..n].chunks_exact_mut(LANES).zip(vs[..n].chunks_exact(LANES)).chain(padded) {
        let lane = |f: fn(&Vertex) -> f32| bytemuck::cast::<[f32; LANES], __m256>(std::array::from_fn(|l| f(&ins[l])));
        let (x, y, z) = (lane(|v| v.position.x), lane(|v| v.position.y), lane(|v| v.position.z));
        let row = |a: f32, b: f32, c: f32, w: f32| {
            _mm256_add_ps(
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(s(a), x), _mm256_mul_ps(s(b), y)), _mm256_mul_ps(s(c), z)),
                s(w),
            )
        };
        let cx = row(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x);
        let cy = row(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y);
        let cz = row(m.x_axis.z, m.y_axis.z, m.z_axis.z, m.w_axis.z);
        let cw = row(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w);
        let xz = _mm256_add_ps(_mm256_mul_ps(s(d.x), x), _mm256_mul_ps(s(d.z), z));
        let yw = _mm256_add_ps(_mm256_mul_ps(s(d.y), y), s(d.w));
        let view_depth = _mm256_xor_ps(_mm256_add_ps(xz, yw), sign);
        let all_finite = _mm256_and_ps(
            _mm256_and_ps(finite(cx), finite(cy)),
            _mm256_and_ps(_mm256_and_ps(finite(cz), finite(cw)), finite(view_depth)),
        );
        // `ClipVolume::codes`.
        let neg_w = _mm256_xor_ps(cw, sign);
        let lt = |a: __m256, b: __m256| _mm256_cmp_ps::<_CMP_LT_OQ>(a, b);
        let gt = |a: __m256, b: __m256| _mm256_cmp_ps::<_CMP_GT_OQ>(a, b);
        let mut outside = _mm256_or_si256(bit(lt(cz, neg_w), 0), bit(lt(cx, neg_w), 2));
        outside = _mm256_or_si256(outside, _mm256_or_si256(bit(gt(cx, cw), 3), bit(lt(cy, neg_w), 4)));
        outside = _mm256_or_si256(outside, bit(gt(cy, cw), 5));
        let zero = s(0.0);
        let gxw = _mm256_mul_ps(gx, cw);
        let gyw = _mm256_mul_ps(gy, cw);
        let mut cut =
            _mm256_or_si256(bit(lt(_mm256_add_ps(cz, cw), zero), 0), bit(lt(_mm256_add_ps(cx, gxw), zero), 2));
        cut = _mm256_or_si256(
            cut,
            _mm256_or_si256(bit(lt(_mm256_sub_ps(gxw, cx), zero), 3), bit(lt(_mm256_add_ps(cy, gyw), zero), 4)),
        );
        cut = _mm256_or_si256(cut, bit(lt(_mm256_sub_ps(gyw, cy), zero), 5));
        if far {
            outside = _mm256_or_si256(outside, bit(gt(cz, cw), 1));
            cut = _mm256_or_si256(cut, bit(lt(_mm256_sub_ps(cw, cz), zero), 1));
        }
        // `project`.
        let q = _mm256_div_ps(s(1.0), cw);
        let sx = _mm256_mul_ps(_mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(cx, q), s(1.0)), s(0.5)), s(t.size.0));
        let sy = _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(s(1.0), _mm256_mul_ps(cy, q)), s(0.5)), s(t.size.1));
        let ((fx, okx), (fy, oky)) = (snap(sx), snap(sy));
        let in_front = _mm256_and_ps(gt(cw, zero), finite(q));
        let cut_none = _mm256_cmp_ps::<_CMP_EQ_OQ>(_mm256_cvtepi32_ps(cut), zero);
        let projected =
            _mm256_and_ps(_mm256_and_ps(_mm256_and_ps(okx, oky), in_front), _mm256_and_ps(all_finite, cut_none));
        let depth = if t.perspective { q } else { _mm256_mul_ps(s(0.5), _mm256_sub_ps(s(1.0), _mm256_mul_ps(cz, q))) };
        // Zeros where the vertex did not project, as the one-vertex loop stores.
        let keep = _mm256_castps_si256(projected);
        let (fx, fy) = (_mm256_and_si256(fx, keep), _mm256_and_si256(fy, keep));
        let (depth, q) = (_mm256_and_ps(depth, projected), _mm256_and_ps(q, projected));
        // The record's last word: outside, cut, finite and projected, a byte each (little-endian).
        let flag = |m: __m256, shift: i32| _mm256_and_si256(_mm256_castps_si256(m), _mm256_set1_epi32(1 << shift));
        let packed = _mm256_or_si256(
            _mm256_or_si256(outside, _mm256_slli_epi32::<8>(cut)),
            _mm256_or_si256(flag(all_finite, 16), flag(projected, 24)),
        );
        // Eight records of six words from six vectors of eight lanes: the first four words of each record
        // by a 4x4 transpose within each 128-bit half, the last two by interleaving.
        let (a, b) = (_mm256_castsi256_ps(fx), _mm256_castsi256_ps(fy));
        let (t0, t1) = (_mm256_unpacklo_ps(a, b), _mm256_unpackhi_ps(a, b));
        let (t2, t3) = (_mm256_unpacklo_ps(depth, q), _mm256_unpackhi_ps(depth, q));
        let heads = [
            _mm256_shuffle_ps::<0x44>(t0, t2),
            _mm256_shuffle_ps::<0xee>(t0, t2),
            _mm256_shuffle_ps::<0x44>(t1, t3),
            _mm256_shuffle_ps::<0xee>(t1, t3),
        ];
        let p = _mm256_castsi256_ps(packed);
        let tails = [_mm256_unpacklo_ps(view_depth, p), _mm256_unpackhi_ps(view_depth, p)];
        let words: &mut [u32] = bytemuck::cast_slice_mut(outs);
        for (l, record) in words.chunks_exact_mut(6).enumerate() {
            // Record l: its head in half l / 4 of heads[l % 4], its tail in half l / 4 of tails[l % 4 / 2],
            // words (l % 2) * 2 .. + 2 of that half.
            let half = |v: __m256| if l < 4 { _mm256_castps256_ps128(v) } else { _mm256_extractf128_ps::<1>(v) };
            let head = bytemuck::cast::<__m128, [u32; 4]>(half(heads[l % 4]));
            let tail = bytemuck::cast::<__m128, [u32; 4]>(half(tails[l % 4 / 2]));
            let t = (l % 2) * 2;
            record[..4].copy_from_slice(&head);
            record[4..].copy_from_slice(&tail[t..t + 2]);
        }
    }
    if let (Some(to), Some(from)) = (out.get_mut(n..all), last_out.get(..rest)) {
        to.copy_from_slice(from);
    }
    all
}
