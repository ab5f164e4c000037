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

/// The texels of eight lanes at columns `x` and rows `y` of a level `size` texels wide and high, stored row
/// by row in `texels`, by one AVX2 gather; `None` when the slice is shorter than the level (no texture built
/// here has such a slice) or the level is empty.
///
/// The bilinear and area texels take four of these a chunk of eight pixels, where 32 lanes moved out of
/// vectors, loaded and moved back cost more. Each coordinate is clamped into its range first (`min`,
/// unsigned): the span loops pass coordinates already wrapped into it, which the clamp leaves as they are,
/// and it makes every index `y * width + x` smaller than `width * height` by construction, so one scalar
/// comparison of that product with the slice's length covers the eight reads (and, once inlined, the four
/// of a bilinear texel), where checking each index took six vector instructions a gather.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) fn gather_texels(
    texels: &[u32],
    (width, height): (u32, u32),
    x: std::arch::x86_64::__m256i,
    y: std::arch::x86_64::__m256i,
) -> Option<std::arch::x86_64::__m256i> {
    use std::arch::x86_64::{
        _mm256_add_epi32, _mm256_i32gather_epi32, _mm256_min_epu32, _mm256_mullo_epi32, _mm256_set1_epi32,
    };
    let level = u64::from(width) * u64::from(height);
    if width == 0 || height == 0 || level > texels.len().min(i32::MAX as usize) as u64 {
        return None;
    }
    let x = _mm256_min_epu32(x, _mm256_set1_epi32((width - 1) as i32));
    let y = _mm256_min_epu32(y, _mm256_set1_epi32((height - 1) as i32));
    let idx = _mm256_add_epi32(_mm256_mullo_epi32(y, _mm256_set1_epi32(width as i32)), x);
    // SAFETY: every lane's column is below `width` and its row below `height` (clamped above, unsigned), so
    // its index is below `width * height`, which is at most `texels.len()` and `i32::MAX` (checked above):
    // each 4-byte read is inside `texels`. The caller's `target_feature` (this function's) guarantees AVX2.
    #[allow(unsafe_code)]
    let v = unsafe { _mm256_i32gather_epi32::<4>(texels.as_ptr().cast::<i32>(), idx) };
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

#[cfg(test)]
mod tests {
    use std::arch::x86_64::__m256i;

    /// `gather_texels` of a level `size` texels wide and high at columns `x` and rows `y`, as an array.
    fn gathered(texels: &[u32], size: (u32, u32), x: [i32; 8], y: [i32; 8]) -> Option<[u32; 8]> {
        assert!(super::super::has_avx2(), "these hosts have AVX2");
        let v = bytemuck::cast::<[i32; 8], __m256i>;
        // SAFETY: the CPU has AVX2 (asserted above).
        #[allow(unsafe_code)]
        let out = unsafe { super::gather_texels(texels, size, v(x), v(y)) };
        out.map(bytemuck::cast::<__m256i, [u32; 8]>)
    }

    #[test]
    fn texels_are_read_by_row_and_column_clamped_into_the_level_and_not_from_a_short_slice() {
        let texels: Vec<u32> = (100..112).collect(); // 4 wide, 3 high
        let x = [0, 1, 2, 3, 0, 1, 9, -1];
        let y = [0, 0, 1, 1, 2, 2, 0, -5];
        // A coordinate outside the level reads its last column or row (unsigned: -1 is the largest).
        assert_eq!(gathered(&texels, (4, 3), x, y), Some([100, 101, 106, 107, 108, 109, 103, 111]));
        assert_eq!(gathered(&texels, (3, 4), x, y), Some([100, 101, 105, 105, 106, 107, 102, 111]));
        assert_eq!(gathered(&texels[..11], (4, 3), x, y), None);
        assert_eq!(gathered(&texels, (4, 0), x, y), None);
        assert_eq!(gathered(&[], (0, 0), x, y), None);
    }
}
