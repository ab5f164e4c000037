//! Small-triangle set-up of flat triangles eight at a time with AVX2, for the triangles that need no
//! clipping.
//!
//! One flat triangle's set-up ([`SmallTriangle::from_corners`] with the depth plane only, after the checks
//! of the per-polygon loop) is a few dozen integer and float operations with one division, all independent
//! from one triangle to the next, so it maps onto eight lanes: each lane's corner records are loaded from
//! the transformed vertices ([`SetupVertex`]) and transposed into vectors (gathers measured slower), and
//! every lane gets its bounding box, area, edge functions, depth plane and packed colour at once; the
//! records go back with an 8x8 transpose, two vectors a record. Each step repeats the one-triangle code
//! operation for operation (the same integer arithmetic, the same IEEE operations in the same order, no
//! fused multiply-add), so a lane's record is bit-identical to the one the scalar path sets up; the caller
//! (`setup::lanes`) keeps the order, the counts and everything a lane cannot decide (clip flags, colours
//! compared, culling, keys), and hands any other polygon to the scalar path.
//!
//! Textured triangles are not taken: with their three more planes they measured slower in lanes than one
//! at a time on the game's frames.

use std::arch::x86_64::{
    __m128, __m256, __m256i, _CMP_GT_OQ, _mm_setzero_ps, _mm256_add_epi32, _mm256_add_ps, _mm256_and_ps,
    _mm256_and_si256, _mm256_andnot_si256, _mm256_blendv_epi8, _mm256_castps_si256, _mm256_castps128_ps256,
    _mm256_castsi256_ps, _mm256_cmp_ps, _mm256_cmpeq_epi32, _mm256_cmpgt_epi32, _mm256_cvtepi32_ps,
    _mm256_cvttps_epi32, _mm256_div_ps, _mm256_insertf128_ps, _mm256_max_epi32, _mm256_max_ps, _mm256_min_epi32,
    _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps, _mm256_mullo_epi32, _mm256_or_si256, _mm256_permute2f128_ps,
    _mm256_set1_epi32, _mm256_set1_ps, _mm256_setzero_si256, _mm256_shuffle_ps, _mm256_slli_epi32, _mm256_srai_epi32,
    _mm256_sub_epi32, _mm256_sub_ps, _mm256_unpackhi_ps, _mm256_unpacklo_ps, _mm256_xor_si256,
};

use super::vertex::SetupVertex;
use crate::render::core::fixed::Fx28_4;
use crate::render::core::mesh::Vertex;
use crate::render::core::small::{EdgeFn, MAX_SIDE, SmallFrame, SmallTriangle, TexPlanes};
use crate::render::simd::Avx2;
use crate::render::simd::x86::load4;

/// Triangles per step.
pub(crate) const LANES: usize = 8;

/// Eight triangles set up lane by lane: which lanes this path takes, and their records.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lanes {
    /// Bit `l` is set when lane `l`'s bounding box is at most [`MAX_SIDE`] pixels each way: when its
    /// corners are projected and need no clipping (the caller checks), a small triangle whose record below
    /// is the one-triangle set-up's (once it is known not to be culled).
    pub(crate) fit: u32,
    /// Bit `l` is set when lane `l`'s box has no pixel centre in the frame: its record is the empty one.
    empty: u32,
    /// Each lane's signed area in raw units squared ([`triangle_area2`](crate::render::core::vertex)).
    pub(crate) area: [i32; LANES],
    /// [`pack_rgb`](crate::render::core::polygon::pack_rgb) of the first corner's colour times the base
    /// colour, for flat triangles (the colour of the triangle when it has one and it is not NaN).
    pub(crate) packed: [i32; LANES],
    /// Each lane's record (unless its box is empty), written with vector stores.
    records: [SmallTriangle; LANES],
}

impl Lanes {
    /// Lane `l`'s record, and the texture planes of a flat triangle (none).
    #[inline(always)]
    pub(crate) fn triangle(&self, l: usize) -> (SmallTriangle, TexPlanes) {
        if self.empty >> l & 1 != 0 {
            let r0 = self.records[l].rows[0];
            let edges = [EdgeFn { at_row: 0, step_x: 0, step_y: 0 }; 3];
            let empty = SmallTriangle { edges, x_columns: 0, rows: [r0, r0], y0: 0.0, depth: [0.0; 3] };
            return (empty, TexPlanes::NONE);
        }
        (self.records[l], TexPlanes::NONE)
    }
}

/// The words of eight records, given as eight vectors of one word each (word `k` of lane `l` in lane `l`
/// of vector `k`), turned into eight vectors of one record each (lane `l`'s words in vector `l`).
#[target_feature(enable = "avx2")]
fn transpose8(w: [__m256; 8]) -> [__m256; 8] {
    let (t0, t1) = (_mm256_unpacklo_ps(w[0], w[1]), _mm256_unpackhi_ps(w[0], w[1]));
    let (t2, t3) = (_mm256_unpacklo_ps(w[2], w[3]), _mm256_unpackhi_ps(w[2], w[3]));
    let (t4, t5) = (_mm256_unpacklo_ps(w[4], w[5]), _mm256_unpackhi_ps(w[4], w[5]));
    let (t6, t7) = (_mm256_unpacklo_ps(w[6], w[7]), _mm256_unpackhi_ps(w[6], w[7]));
    // Lanes 0-3 of words 0-3 (and lanes 4-7 in the upper halves), then of words 4-7.
    let (s0, s1) = (_mm256_shuffle_ps::<0x44>(t0, t2), _mm256_shuffle_ps::<0xee>(t0, t2));
    let (s2, s3) = (_mm256_shuffle_ps::<0x44>(t1, t3), _mm256_shuffle_ps::<0xee>(t1, t3));
    let (s4, s5) = (_mm256_shuffle_ps::<0x44>(t4, t6), _mm256_shuffle_ps::<0xee>(t4, t6));
    let (s6, s7) = (_mm256_shuffle_ps::<0x44>(t5, t7), _mm256_shuffle_ps::<0xee>(t5, t7));
    [
        _mm256_permute2f128_ps::<0x20>(s0, s4),
        _mm256_permute2f128_ps::<0x20>(s1, s5),
        _mm256_permute2f128_ps::<0x20>(s2, s6),
        _mm256_permute2f128_ps::<0x20>(s3, s7),
        _mm256_permute2f128_ps::<0x31>(s0, s4),
        _mm256_permute2f128_ps::<0x31>(s1, s5),
        _mm256_permute2f128_ps::<0x31>(s2, s6),
        _mm256_permute2f128_ps::<0x31>(s3, s7),
    ]
}

/// Sets up the flat triangles whose corners are `ids[0][l]`, `ids[1][l]`, `ids[2][l]` in `vertices`
/// (transformed from `mesh`), of a material of colour `base_color`, for `frame` (its width, and its rows'
/// reach, which widens the box): the depth plane and the packed colour. The indices are the mesh's, which building it checked.
pub(crate) fn set_up(
    _: Avx2,
    (vertices, mesh): (&[SetupVertex], &[Vertex]),
    ids: &[[u32; LANES]; 3],
    base_color: [f32; 4],
    frame: SmallFrame,
) -> Lanes {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all `set_up_avx2` needs.
    #[allow(unsafe_code)]
    unsafe {
        set_up_avx2((vertices, mesh), ids, base_color, frame)
    }
}

/// `pack_rgb` of the colours `c` (channels in lanes), operation for operation: every colour the caller
/// uses is a number, so the order of each maximum's and minimum's operands does not matter.
#[target_feature(enable = "avx2")]
fn pack_rgb_x8(c: [__m256; 3]) -> __m256i {
    let s = _mm256_set1_ps;
    let magic = s(8_388_608.0);
    let whole = c.map(|c| {
        let v = _mm256_min_ps(_mm256_max_ps(_mm256_add_ps(_mm256_mul_ps(c, s(255.0)), s(0.5)), s(0.0)), s(255.0));
        let rounded = _mm256_sub_ps(_mm256_add_ps(v, magic), magic);
        _mm256_sub_ps(rounded, _mm256_and_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(rounded, v), s(1.0)))
    });
    let rg = _mm256_add_ps(_mm256_mul_ps(whole[0], s(65_536.0)), _mm256_mul_ps(whole[1], s(256.0)));
    _mm256_cvttps_epi32(_mm256_add_ps(rg, whole[2]))
}

/// One corner of eight lanes: raw position and depth.
struct Corners {
    x: __m256i,
    y: __m256i,
    depth: __m256,
}

/// The four words lane `l` finds in `rows[l]`, turned into four vectors of eight lanes (word `k` of every
/// lane in vector `k`): eight loads and a transpose, several times cheaper here than four gathers.
#[target_feature(enable = "avx2")]
fn transpose(rows: [__m128; LANES]) -> [__m256; 4] {
    // Lanes `k` and `k + 4` side by side, then a 4x4 transpose within each 128-bit half.
    let pair = |k: usize| _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(rows[k]), rows[k + 4]);
    let (a0, a1, a2, a3) = (pair(0), pair(1), pair(2), pair(3));
    let (t0, t1) = (_mm256_unpacklo_ps(a0, a1), _mm256_unpacklo_ps(a2, a3));
    let (t2, t3) = (_mm256_unpackhi_ps(a0, a1), _mm256_unpackhi_ps(a2, a3));
    [
        _mm256_shuffle_ps::<0x44>(t0, t1),
        _mm256_shuffle_ps::<0xee>(t0, t1),
        _mm256_shuffle_ps::<0x44>(t2, t3),
        _mm256_shuffle_ps::<0xee>(t2, t3),
    ]
}

/// Loads corner `ids` of eight lanes.
#[target_feature(enable = "avx2")]
fn corners(vertices: &[SetupVertex], ids: &[u32; LANES]) -> Corners {
    let record = |l: usize| {
        let words: &[f32; 6] = bytemuck::cast_ref(&vertices[ids[l] as usize]);
        load4::<f32, __m128>(words).unwrap_or(_mm_setzero_ps())
    };
    let [x, y, depth, _] = transpose(std::array::from_fn(record));
    Corners { x: _mm256_castps_si256(x), y: _mm256_castps_si256(y), depth }
}

// long: one AVX2 body; split into functions its vectors would pass through memory (a `#[target_feature]` function cannot be `inline(always)`).
/// [`set_up`]'s body, compiled for AVX2.
#[target_feature(enable = "avx2")]
fn set_up_avx2(
    (vertices, mesh): (&[SetupVertex], &[Vertex]),
    ids: &[[u32; LANES]; 3],
    base_color: [f32; 4],
    SmallFrame { width, reach, rows }: SmallFrame,
) -> Lanes {
    let [p0, p1, p2] = [corners(vertices, &ids[0]), corners(vertices, &ids[1]), corners(vertices, &ids[2])];
    let i = _mm256_set1_epi32;
    let zero = _mm256_setzero_si256();
    // The box: the first centres at or after the corners' least and greatest coordinates (projected corners
    // are within 2^30 raw units, so `+ 7` cannot overflow).
    let first = |v: __m256i| _mm256_srai_epi32::<4>(_mm256_add_epi32(v, i(Fx28_4::ONE - 1 - Fx28_4::HALF)));
    let min3 = |a, b, c| _mm256_min_epi32(_mm256_min_epi32(a, b), c);
    let max3 = |a, b, c| _mm256_max_epi32(_mm256_max_epi32(a, b), c);
    // Widened as `small_setup::bounds` widens it for a frame whose rows sample shifted columns.
    let grow = i(if reach > 0 { reach + 1 } else { 0 });
    let col0 = first(_mm256_sub_epi32(min3(p0.x, p1.x, p2.x), grow));
    let col1 = first(_mm256_add_epi32(max3(p0.x, p1.x, p2.x), grow));
    let (row0, row1) = (first(min3(p0.y, p1.y, p2.y)), first(max3(p0.y, p1.y, p2.y)));
    let small = _mm256_and_si256(
        _mm256_cmpgt_epi32(i(MAX_SIDE + 1), _mm256_sub_epi32(col1, col0)),
        _mm256_cmpgt_epi32(i(rows + 1), _mm256_sub_epi32(row1, row0)),
    );
    let fit = _mm256_movemask_ps(_mm256_castsi256_ps(small)) as u32;
    // The area from the first corner: within a box that fits every product is below 2^19, and equals the
    // sum of the corners' cross products exactly (lanes that do not fit are not used).
    let (e1x, e1y) = (_mm256_sub_epi32(p1.x, p0.x), _mm256_sub_epi32(p1.y, p0.y));
    let (e2x, e2y) = (_mm256_sub_epi32(p2.x, p0.x), _mm256_sub_epi32(p2.y, p0.y));
    let area = _mm256_sub_epi32(_mm256_mullo_epi32(e1x, e2y), _mm256_mullo_epi32(e2x, e1y));
    let x_start = _mm256_max_epi32(col0, zero);
    let x_end = _mm256_min_epi32(col1, i(width));
    let some = _mm256_and_si256(_mm256_cmpgt_epi32(x_end, x_start), _mm256_cmpgt_epi32(row1, row0));
    let empty = !_mm256_movemask_ps(_mm256_castsi256_ps(some)) as u32 & 0xff;
    let centre = |v: __m256i| _mm256_add_epi32(_mm256_slli_epi32::<4>(v), i(Fx28_4::HALF));
    let (cx, cy) = (centre(x_start), centre(row0));
    // `EdgeFn::new`: the function from `p` to `q`, negated when the area is positive.
    let flip = _mm256_cmpgt_epi32(area, zero);
    let negate = |v: __m256i| _mm256_sub_epi32(_mm256_xor_si256(v, flip), flip);
    let edge = |p: &Corners, q: &Corners| {
        let (dx, dy) = (_mm256_sub_epi32(q.x, p.x), _mm256_sub_epi32(q.y, p.y));
        let f = _mm256_sub_epi32(
            _mm256_mullo_epi32(_mm256_sub_epi32(cx, p.x), dy),
            _mm256_mullo_epi32(dx, _mm256_sub_epi32(cy, p.y)),
        );
        let (f, dx, dy) = (negate(f), negate(dx), negate(dy));
        // After the flip a right edge is one going up (`dy < 0`); its mask (-1) takes the one away.
        let right = _mm256_cmpgt_epi32(zero, dy);
        let flat = _mm256_cmpeq_epi32(dy, zero);
        let at_row = _mm256_blendv_epi8(_mm256_add_epi32(_mm256_add_epi32(f, i(1)), right), i(1), flat);
        let step_y = _mm256_andnot_si256(flat, _mm256_slli_epi32::<4>(_mm256_sub_epi32(zero, dx)));
        [at_row, _mm256_slli_epi32::<4>(dy), step_y]
    };
    let edges = [edge(&p0, &p1), edge(&p1, &p2), edge(&p2, &p0)];
    // The depth's plane, as `from_corners` computes it.
    let s = _mm256_set1_ps;
    let to_f32 = |v: __m256i| _mm256_mul_ps(_mm256_cvtepi32_ps(v), s(1.0 / Fx28_4::ONE as f32));
    let (x0, y0) = (to_f32(p0.x), to_f32(p0.y));
    let (fe1x, fe1y) = (_mm256_sub_ps(to_f32(p1.x), x0), _mm256_sub_ps(to_f32(p1.y), y0));
    let (fe2x, fe2y) = (_mm256_sub_ps(to_f32(p2.x), x0), _mm256_sub_ps(to_f32(p2.y), y0));
    let inv_det = _mm256_div_ps(s(256.0), _mm256_cvtepi32_ps(area));
    let ox = _mm256_sub_ps(_mm256_add_ps(_mm256_cvtepi32_ps(x_start), s(0.5)), x0);
    let (d1, d2) = (_mm256_sub_ps(p1.depth, p0.depth), _mm256_sub_ps(p2.depth, p0.depth));
    let dadx = _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(d1, fe2y), _mm256_mul_ps(d2, fe1y)), inv_det);
    let dady = _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(d2, fe1x), _mm256_mul_ps(d1, fe2x)), inv_det);
    let a0 = _mm256_add_ps(p0.depth, _mm256_mul_ps(dadx, ox));
    // The records' sixteen words in their order (`SmallTriangle` is `repr(C)`), eight lanes each, turned
    // into two vectors a record.
    let columns = _mm256_or_si256(x_start, _mm256_slli_epi32::<24>(_mm256_sub_epi32(x_end, x_start)));
    let e = |k: usize, j: usize| _mm256_castsi256_ps(edges[k][j]);
    let f = _mm256_castsi256_ps;
    let low = transpose8([e(0, 0), e(0, 1), e(0, 2), e(1, 0), e(1, 1), e(1, 2), e(2, 0), e(2, 1)]);
    let high = transpose8([e(2, 2), f(columns), f(row0), f(row1), y0, a0, dadx, dady]);
    // A record is sixteen 4-byte words in this order, plain old data (its layout asserted in `core::small`).
    let record = |l: usize| bytemuck::cast::<[__m256; 2], SmallTriangle>([low[l], high[l]]);
    // The first corner's colour times the material's, packed.
    let color = |l: usize| __m128::from(mesh[ids[0][l] as usize].color);
    let [r, g, b, _] = transpose(std::array::from_fn(color));
    let [br, bg, bb, _] = base_color;
    let packed = pack_rgb_x8([_mm256_mul_ps(r, s(br)), _mm256_mul_ps(g, s(bg)), _mm256_mul_ps(b, s(bb))]);
    Lanes {
        fit,
        empty,
        area: bytemuck::cast(area),
        packed: bytemuck::cast(packed),
        records: std::array::from_fn(record),
    }
}
