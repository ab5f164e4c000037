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

/// The texels of eight lanes that lie on one row of a level `width` texels wide, within eight columns
/// from the first lane (`ascending`) or the last, by one load and one permute; `None` for any other lanes
/// (and where the eight texels from that column would run past the slice's end). Each lane's column is
/// in the low 16 bits of `packed` and its row in the high 16, as the depth-first loop keeps them, both
/// already within the level.
///
/// Why: eight neighbouring pixels of a magnified texture read a handful of neighbouring texels, and an
/// eight-lane gather costs more than a load and a permute on this host (a full-screen magnified quad took
/// 0.75x the time with its gathers left out). Lanes on two rows differ by at least `65536 - (width - 1)` in
/// `packed`, more than 7 for a level narrower than [`ONE_ROW_WIDTH`], so one unsigned distance from the
/// chosen lane tells both conditions.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) fn one_row_texels(
    texels: &[u32],
    width: u32,
    packed: std::arch::x86_64::__m256i,
    ascending: bool,
) -> Option<std::arch::x86_64::__m256i> {
    use std::arch::x86_64::{
        _mm_cvtsi128_si32, _mm256_castsi256_si128, _mm256_cmpeq_epi32, _mm256_extract_epi32, _mm256_min_epu32,
        _mm256_movemask_epi8, _mm256_permutevar8x32_epi32, _mm256_set1_epi32, _mm256_sub_epi32,
    };
    if width >= ONE_ROW_WIDTH {
        return None;
    }
    let first =
        if ascending { _mm_cvtsi128_si32(_mm256_castsi256_si128(packed)) } else { _mm256_extract_epi32::<7>(packed) };
    let offset = _mm256_sub_epi32(packed, _mm256_set1_epi32(first));
    let near = _mm256_cmpeq_epi32(_mm256_min_epu32(offset, _mm256_set1_epi32(7)), offset);
    if _mm256_movemask_epi8(near) != -1 {
        return None;
    }
    let first = first as u32;
    let at = (first >> 16) as usize * width as usize + (first & 0xffff) as usize;
    let row: std::arch::x86_64::__m256i = load8(texels.get(at..)?)?;
    Some(_mm256_permutevar8x32_epi32(row, offset))
}

/// Levels at least this wide are never read by [`one_row_texels`] (lanes on neighbouring rows could then be
/// within eight of each other in its packed form).
pub(crate) const ONE_ROW_WIDTH: u32 = 65_536 - 8;

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

    /// `one_row_texels` of a level `width` texels wide at columns `x` and rows `y`, as an array.
    fn one_row(texels: &[u32], width: u32, x: [i32; 8], y: [i32; 8], ascending: bool) -> Option<[u32; 8]> {
        assert!(super::super::has_avx2(), "these hosts have AVX2");
        let packed: [i32; 8] = std::array::from_fn(|l| x[l] | y[l] << 16);
        // SAFETY: the CPU has AVX2 (asserted above).
        #[allow(unsafe_code)]
        let out = unsafe { super::one_row_texels(texels, width, bytemuck::cast(packed), ascending) };
        out.map(bytemuck::cast::<__m256i, [u32; 8]>)
    }

    #[test]
    fn texels_on_one_row_within_eight_columns_are_read_as_a_gather_reads_them_and_no_others() {
        // A small generator of its own: this module uses no other (`render/simd` is below `render/core`).
        struct Rng(u64);
        impl Rng {
            fn next(&mut self) -> u32 {
                self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (self.0 >> 33) as u32
            }
            fn below(&mut self, n: u32) -> u32 {
                self.next() % n
            }
        }
        let mut rng = Rng(5);
        let (mut taken, mut refused) = (0, 0);
        for case in 0..20_000 {
            let (w, h) = ([9u32, 16, 40, 256, 1000][rng.below(5) as usize], [1u32, 2, 7, 64][rng.below(4) as usize]);
            let texels: Vec<u32> = (0..w * h).map(|_| rng.next()).collect();
            // Columns from a base within a few texels of it, in either order; now and then a lane one row
            // down, one column too far, or past the level's end.
            let (base_x, base_y) = (rng.below(w) as i32, rng.below(h) as i32);
            let ascending = case % 2 == 0;
            let mut x: [i32; 8] = std::array::from_fn(|l| {
                let step = (l as i32 * rng.below(3) as i32).min(7) / 2;
                (if ascending { base_x + step } else { base_x - step }).clamp(0, w as i32 - 1)
            });
            let mut y = [base_y; 8];
            match case % 5 {
                1 => y[rng.below(8) as usize] = (base_y + 1).min(h as i32 - 1),
                2 => x[rng.below(8) as usize] = (base_x + 8).min(w as i32 - 1),
                3 => x[rng.below(8) as usize] = rng.below(w) as i32,
                _ => {}
            }
            let (fast, gather) = (one_row(&texels, w, x, y, ascending), gathered(&texels, (w, h), x, y));
            let first = if ascending { 0 } else { 7 };
            let within = (0..8).all(|l| y[l] == y[first] && (0..8).contains(&(x[l] - x[first])));
            let fits = (y[first] * w as i32 + x[first]) as usize + 8 <= texels.len();
            match fast {
                Some(t) => {
                    assert!(within && fits, "case {case}: taken for {x:?} {y:?} ({w}x{h}, ascending {ascending})");
                    assert_eq!(Some(t), gather, "case {case}: {x:?} {y:?}");
                    taken += 1;
                }
                None => {
                    assert!(!(within && fits), "case {case}: refused {x:?} {y:?} ({w}x{h}, ascending {ascending})");
                    refused += 1;
                }
            }
        }
        assert!(taken > 5_000 && refused > 3_000, "{taken} taken, {refused} refused");
        // A level as wide as the packed form allows is never read this way.
        let wide = vec![7u32; super::ONE_ROW_WIDTH as usize + 8];
        assert_eq!(one_row(&wide, super::ONE_ROW_WIDTH, [0; 8], [0; 8], true), None);
    }
}
