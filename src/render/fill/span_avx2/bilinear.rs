//! Bilinear texels of one mip level on eight lanes: the samples' top-left texels and weights, their
//! columns and rows wrapped, and the 2x2 blend (which the depth-first loop runs in its second pass, from
//! what its first kept). Macros, as the rest of the chunk's steps: a `#[target_feature]` function cannot be
//! `inline(always)`.

/// The 2x2 texels of one level at wrapped columns `x`, `x + 1` and rows `y`, `y + 1` on eight lanes, blended
/// by `ax` across and then `ay` down (in 1/256): a bilinear texel, or an anisotropic probe's box.
///
/// Three [`blend_x8`]s, bit for bit, with the two across kept as 16-bit channels for the one down (a blend's
/// packed result split again into its channels is the same two vectors).
macro_rules! blend_2x2_x8 {
    ($tex:expr, $columns:expr, $rows:expr, $weights:expr) => {{
        let (tex, columns, rows, (ax, ay)): (&Texture, (__m256i, __m256i), (__m256i, __m256i), (__m256i, __m256i)) =
            ($tex, $columns, $rows, $weights);
        let texels = tex.texels();
        let size = (tex.width(), tex.height());
        let fetch = |y: __m256i, x: __m256i| {
            crate::render::simd::x86::gather_texels(texels, size, x, y).unwrap_or_else(|| {
                let (xs, ys): ([u32; LANES], [u32; LANES]) = (bytemuck::cast(x), bytemuck::cast(y));
                let at = |l: usize| ys[l].wrapping_mul(size.0).wrapping_add(xs[l]) as usize;
                let out: [u32; LANES] = std::array::from_fn(|l| texels.get(at(l)).copied().unwrap_or(0));
                bytemuck::cast::<[u32; LANES], __m256i>(out)
            })
        };
        let ((x, x1), (y, y1)) = (columns, rows);
        let [a, b, c, d] = [fetch(y, x), fetch(y, x1), fetch(y1, x), fetch(y1, x1)];
        let m = _mm256_set1_epi32(0x00ff_00ff);
        let half = _mm256_set1_epi32(0x0080_0080);
        let pair = |w: __m256i| _mm256_or_si256(w, _mm256_slli_epi32::<16>(w));
        let weights = |w: __m256i| (pair(w), pair(_mm256_sub_epi32(_mm256_set1_epi32(256), w)));
        // A texel's red and blue, and its green and alpha, each in the low byte of a 16-bit lane.
        let split = |t: __m256i| (_mm256_and_si256(t, m), _mm256_and_si256(_mm256_srli_epi32::<8>(t), m));
        // `x * (256 - w) + y * w + 128` per 16-bit lane (at most 255 * 256 + 128: no carry between lanes).
        let mix = |x: __m256i, y: __m256i, (wy, wx): (__m256i, __m256i)| {
            _mm256_add_epi16(_mm256_add_epi16(_mm256_mullo_epi16(x, wx), _mm256_mullo_epi16(y, wy)), half)
        };
        let across = |x: __m256i, y: __m256i| {
            let ((x_rb, x_ag), (y_rb, y_ag), w) = (split(x), split(y), weights(ax));
            (_mm256_srli_epi16::<8>(mix(x_rb, y_rb, w)), _mm256_srli_epi16::<8>(mix(x_ag, y_ag, w)))
        };
        let ((top_rb, top_ag), (bottom_rb, bottom_ag)) = (across(a, b), across(c, d));
        let w = weights(ay);
        let rb = _mm256_srli_epi16::<8>(mix(top_rb, bottom_rb, w));
        _mm256_or_si256(rb, _mm256_andnot_si256(m, mix(top_ag, bottom_ag, w)))
    }};
}

/// The top-left texels (columns and rows, before wrapping) of the bilinear samples at texture coordinates
/// `u`, `v` on eight lanes in a level `size` texels wide and high, and the weights of the texels right of and
/// below them, in 1/256 (0..=255). `in_range` says the drawn lanes' texel coordinates are finite and within
/// `±2^22` ([`Setup::texels_in_range`](crate::render::fill::row::Setup::texels_in_range)).
macro_rules! bilinear_corner_x8 {
    ($u:expr, $v:expr, $size:expr, $in_range:expr) => {{
        let (u, v, (w, h)): (__m256, __m256, (u32, u32)) = ($u, $v, $size);
        // In 1/256 texel, the centres at whole numbers. Within `±2^22` texels (`in_range`) that is within
        // `±2^30`, where the plain truncation corrected downwards is the floor.
        let position = |u: __m256, size: u32| {
            let p = _mm256_sub_ps(_mm256_mul_ps(u, _mm256_set1_ps(size as f32 * 256.0)), _mm256_set1_ps(128.0));
            if $in_range { floor_in_range_x8!(p) } else { floor_i32x8!(p) }
        };
        let (px, py) = (position(u, w), position(v, h));
        let byte = _mm256_set1_epi32(255);
        (
            (_mm256_srai_epi32::<8>(px), _mm256_srai_epi32::<8>(py)),
            (_mm256_and_si256(px, byte), _mm256_and_si256(py, byte)),
        )
    }};
}

/// The wrapped columns `x`, `x + 1` and rows `y`, `y + 1` of bilinear samples whose top-left texels are at
/// `x`, `y` in a level `size` texels wide and high, or `None` for wrap modes drawn a lane at a time.
macro_rules! bilinear_wrap_x8 {
    ($x:expr, $y:expr, $size:expr, $sampler:expr) => {{
        let (x, y, (w, h), sampler): (__m256i, __m256i, (u32, u32), Sampler) = ($x, $y, $size, $sampler);
        let one = _mm256_set1_epi32(1);
        let (x1, y1) = (_mm256_add_epi32(x, one), _mm256_add_epi32(y, one));
        let columns = wrap_x8!(x, w, sampler.wrap_s).zip(wrap_x8!(x1, w, sampler.wrap_s));
        let rows = wrap_x8!(y, h, sampler.wrap_t).zip(wrap_x8!(y1, h, sampler.wrap_t));
        columns.zip(rows)
    }};
}

/// `bilinear` on eight lanes: the bilinear texels of one level at texture coordinates `u`, `v`; or, given
/// the footprint's extents across and down, its `area` texels. `in_range` says the drawn lanes' texel
/// coordinates are finite and within `±2^22` ([`Setup::texels_in_range`]).
macro_rules! bilinear_x8 {
    ($u:expr, $v:expr, $tex:expr, $sampler:expr, $in_range:expr) => {
        bilinear_x8!($u, $v, $tex, $sampler, $in_range, None)
    };
    ($u:expr, $v:expr, $tex:expr, $sampler:expr, $in_range:expr, $extent:expr) => {{
        let (u, v, tex, sampler, extent): (__m256, __m256, &Texture, Sampler, Option<(__m256, __m256)>) =
            ($u, $v, $tex, $sampler, $extent);
        let size = (tex.width(), tex.height());
        let ((x, y), (ax, ay)) = bilinear_corner_x8!(u, v, size, $in_range);
        let (ax, ay) = match extent {
            Some((across, down)) => (area_weight_x8!(ax, across), area_weight_x8!(ay, down)),
            None => (ax, ay),
        };
        match bilinear_wrap_x8!(x, y, size, sampler) {
            Some((columns, rows)) => blend_2x2_x8!(tex, columns, rows, (ax, ay)),
            None => {
                let (us, vs): ([f32; LANES], [f32; LANES]) = (bytemuck::cast(u), bytemuck::cast(v));
                let out: [u32; LANES] = match extent {
                    Some((across, down)) => {
                        let (a, d): ([f32; LANES], [f32; LANES]) = (bytemuck::cast(across), bytemuck::cast(down));
                        std::array::from_fn(|l| tex.area(us[l], vs[l], [a[l], d[l]], sampler))
                    }
                    None => std::array::from_fn(|l| tex.bilinear(us[l], vs[l], sampler)),
                };
                bytemuck::cast::<[u32; LANES], __m256i>(out)
            }
        }
    }};
}
