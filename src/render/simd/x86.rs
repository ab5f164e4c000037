//! Helpers the AVX2 loops share: a vector register's worth of values moved between a slice and a register.
//!
//! Each copies a fixed-size array (`[T; N]`, the register's lanes) and casts it, which compiles to one
//! unaligned vector load or store once the slice's length has been checked.

/// Loads a `V` of `N` lanes from the start of a slice of its lanes' type (`None` when the slice is shorter).
#[inline(always)]
fn load_lanes<const N: usize, T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    let a: &[T; N] = s.get(..N)?.try_into().ok()?;
    Some(bytemuck::cast::<[T; N], V>(*a))
}

/// Stores a `V` of `N` lanes at the start of a slice of its lanes' type (nothing when the slice is shorter).
#[inline(always)]
fn store_lanes<const N: usize, T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    if let Some(d) = s.get_mut(..N) {
        d.copy_from_slice(&bytemuck::cast::<V, [T; N]>(v));
    }
}

/// Loads four 32-bit lanes (an SSE register, as the narrow small-triangle fill uses).
#[inline(always)]
pub(crate) fn load4<T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    load_lanes::<4, T, V>(s)
}

/// Stores four 32-bit lanes.
#[inline(always)]
pub(crate) fn store4<T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    store_lanes::<4, T, V>(s, v);
}

/// Stores eight 32-bit lanes (an AVX register, as the span chunks use).
#[inline(always)]
pub(crate) fn store8<T: bytemuck::Pod, V: bytemuck::Pod>(s: &mut [T], v: V) {
    store_lanes::<8, T, V>(s, v);
}

/// Loads eight 32-bit lanes.
#[inline(always)]
pub(crate) fn load8<T: bytemuck::Pod, V: bytemuck::Pod>(s: &[T]) -> Option<V> {
    load_lanes::<8, T, V>(s)
}

/// The eight words of `s` at the indices `idx`, by one AVX2 gather, when every index is below `s.len()`;
/// `None` when one is not (or `s` is too long for 32-bit indices).
///
/// The bilinear texels take four of these a chunk of eight pixels, where 32 lanes moved out of vectors,
/// loaded and moved back cost more.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) fn gather8(s: &[u32], idx: std::arch::x86_64::__m256i) -> Option<std::arch::x86_64::__m256i> {
    use std::arch::x86_64::{
        _mm256_castsi256_ps, _mm256_cmpgt_epi32, _mm256_i32gather_epi32, _mm256_movemask_ps, _mm256_set1_epi32,
    };
    let len = i32::try_from(s.len()).ok()?;
    // Every lane in `0..len`: `len > idx` and `idx > -1`, signed.
    let below = _mm256_cmpgt_epi32(_mm256_set1_epi32(len), idx);
    let above = _mm256_cmpgt_epi32(idx, _mm256_set1_epi32(-1));
    let inside = _mm256_movemask_ps(_mm256_castsi256_ps(below)) & _mm256_movemask_ps(_mm256_castsi256_ps(above));
    if inside != 0xff {
        return None;
    }
    // SAFETY: every lane's index is in `0..s.len()` (checked above), so each 4-byte read is inside `s`; the
    // caller's `target_feature` (this function's) guarantees AVX2.
    #[allow(unsafe_code)]
    let v = unsafe { _mm256_i32gather_epi32::<4>(s.as_ptr().cast::<i32>(), idx) };
    Some(v)
}

/// The AVX2 intrinsics the span loops' macros expand to, in one list: a macro's body names them in the scope
/// it is expanded in, so each file that expands them (`span_avx2` and its `rows` and `points`) imports this
/// whole (three copies of a 40-name list kept in step before).
pub(crate) mod span {
    pub(crate) use std::arch::x86_64::{
        __m256, __m256i, _CMP_GE_OQ, _CMP_GT_OQ, _CMP_LT_OQ, _CMP_UNORD_Q, _mm256_add_epi16, _mm256_add_epi32,
        _mm256_add_ps, _mm256_and_ps, _mm256_and_si256, _mm256_andnot_si256, _mm256_blendv_epi8, _mm256_blendv_ps,
        _mm256_castps_si256, _mm256_castsi256_ps, _mm256_cmp_ps, _mm256_cmpeq_epi32, _mm256_cmpgt_epi32,
        _mm256_cvtepi32_ps, _mm256_cvttps_epi32, _mm256_div_ps, _mm256_max_epi32, _mm256_max_ps, _mm256_min_epi32,
        _mm256_min_ps, _mm256_movemask_ps, _mm256_mul_ps, _mm256_mullo_epi16, _mm256_mullo_epi32, _mm256_or_si256,
        _mm256_set1_epi32, _mm256_set1_ps, _mm256_setr_epi32, _mm256_setr_ps, _mm256_setzero_ps, _mm256_setzero_si256,
        _mm256_slli_epi32, _mm256_srai_epi32, _mm256_srli_epi16, _mm256_srli_epi32, _mm256_sub_epi32, _mm256_sub_ps,
    };
}
