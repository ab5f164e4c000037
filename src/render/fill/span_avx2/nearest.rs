//! The nearest texels of one mip level on eight lanes: their columns and rows (which the depth-first loop
//! turns into indices and keeps between its passes) and the texels themselves. Macros, as the rest of the
//! chunk's steps: a `#[target_feature]` function cannot be `inline(always)`.

/// The columns and rows, before wrapping, of the nearest texels at texture coordinates `u`, `v` on eight
/// lanes in a level `(w, h)` texels in size; `in_range` when the coordinates are known to be finite and
/// within `±2^22` texels ([`Setup::texels_in_range`](crate::render::fill::row::Setup::texels_in_range)).
macro_rules! texel_xy_x8 {
    ($u:expr, $v:expr, ($w:expr, $h:expr), $in_range:expr) => {{
        let fx = _mm256_mul_ps($u, _mm256_set1_ps($w as f32));
        let fy = _mm256_mul_ps($v, _mm256_set1_ps($h as f32));
        if $in_range { (floor_in_range_x8!(fx), floor_in_range_x8!(fy)) } else { (floor_i32x8!(fx), floor_i32x8!(fy)) }
    }};
}

/// The nearest texels of one texture (one mip level) at texture coordinates `u`, `v` on eight lanes.
macro_rules! texels_x8 {
    ($u:expr, $v:expr, $tex:expr, $sampler:expr, $in_range:expr) => {{
        let (u, v, tex, sampler): (__m256, __m256, &Texture, Sampler) = ($u, $v, $tex, $sampler);
        let (xi, yi) = texel_xy_x8!(u, v, (tex.width(), tex.height()), $in_range);
        let texels = tex.texels();
        let wrapped = wrap_x8!(xi, tex.width(), sampler.wrap_s).zip(wrap_x8!(yi, tex.height(), sampler.wrap_t));
        let out: [u32; LANES] = match wrapped {
            Some((wx, wy)) => {
                // Both are in `0..size` now and `width * height` texels exist, so the index is in range
                // (the lookup is still checked: a check that never fails costs little beside the load).
                let row_start = _mm256_mullo_epi32(wy, _mm256_set1_epi32(tex.width() as i32));
                let idx: [u32; LANES] = bytemuck::cast(_mm256_add_epi32(row_start, wx));
                std::array::from_fn(|l| texels.get(idx[l] as usize).copied().unwrap_or(0))
            }
            None => {
                let (xs, ys): ([i32; LANES], [i32; LANES]) = (bytemuck::cast(xi), bytemuck::cast(yi));
                std::array::from_fn(|l| tex.texel(xs[l], ys[l], sampler))
            }
        };
        bytemuck::cast::<[u32; LANES], __m256i>(out)
    }};
}
