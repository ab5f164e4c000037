//! One pixel's samples as vector lanes: which samples a row covers, which pass the depth test, the samples
//! a polygon writes, and the sum of their colours.
//!
//! An anti-aliased frame spends most of its extra time in the pixels an edge crosses, and each of them
//! loops over its `N` samples several times. Written as plain loops that build a bit mask, those loops
//! stay scalar (a compare and a branch per sample), so on x86-64 each operation here works four samples
//! at a time with SSE2, which every x86-64 target has (no run-time detection). Every function has a
//! portable twin, the reference the tests hold the vector one to bit for bit, and which other
//! architectures run. `N` is 4, 8 or 16 (a multiple of four); bit `j` of a mask is sample `j`.

/// Calls the SSE2 body of an operation where the target has SSE2, its portable twin elsewhere.
macro_rules! sse2_or_portable {
    ($f:ident($($arg:expr),*)) => {{
        #[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
        // SAFETY: the build's target has SSE2 (the `cfg` above; every x86-64 target does), which is all the
        // body's `#[target_feature]` asks for.
        #[allow(unsafe_code)]
        let out = unsafe { sse2::$f($($arg),*) };
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse2")))]
        let out = portable::$f($($arg),*);
        out
    }};
}

/// The samples `j` whose run `l[j]..r[j]` holds pixel `x`.
#[inline(always)]
pub(crate) fn within<const N: usize>(l: &[i32; N], r: &[i32; N], x: i32) -> u16 {
    sse2_or_portable!(within(l, r, x))
}

/// The samples of `mask` whose depth, `centre + dz[j]`, is nearer (greater) than `old[j]`.
#[inline(always)]
pub(crate) fn nearer<const N: usize>(mask: u16, centre: f32, dz: &[f32; N], old: &[f32; N]) -> u16 {
    sse2_or_portable!(nearer(mask, centre, dz, old))
}

/// Sets the samples of `pass` in `colors` to `c`.
#[inline(always)]
pub(crate) fn write_colour<const N: usize>(colors: &mut [u32; N], pass: u16, c: u32) {
    sse2_or_portable!(write_colour(colors, pass, c))
}

/// Sets the samples `j` of `pass` in `depths` to `centre + dz[j]`.
#[inline(always)]
pub(crate) fn write_depth<const N: usize>(depths: &mut [f32; N], pass: u16, centre: f32, dz: &[f32; N]) {
    sse2_or_portable!(write_depth(depths, pass, centre, dz))
}

/// The sums of the red, green and blue channels of `colors` (`0x00rrggbb`).
#[inline(always)]
pub(crate) fn channel_sums<const N: usize>(colors: &[u32; N]) -> [u32; 3] {
    sse2_or_portable!(channel_sums(colors))
}

/// The reference: one sample at a time.
#[cfg_attr(all(target_arch = "x86_64", target_feature = "sse2"), allow(dead_code))]
mod portable {
    pub(super) fn within<const N: usize>(l: &[i32; N], r: &[i32; N], x: i32) -> u16 {
        (0..N).fold(0, |m, j| m | u16::from((l[j] <= x) & (x < r[j])) << j)
    }

    pub(super) fn nearer<const N: usize>(mask: u16, centre: f32, dz: &[f32; N], old: &[f32; N]) -> u16 {
        (0..N).fold(0, |m, j| m | u16::from((mask >> j & 1 == 1) & (centre + dz[j] > old[j])) << j)
    }

    pub(super) fn write_colour<const N: usize>(colors: &mut [u32; N], pass: u16, c: u32) {
        for (j, s) in colors.iter_mut().enumerate() {
            if pass >> j & 1 == 1 {
                *s = c;
            }
        }
    }

    pub(super) fn write_depth<const N: usize>(depths: &mut [f32; N], pass: u16, centre: f32, dz: &[f32; N]) {
        for (j, s) in depths.iter_mut().enumerate() {
            if pass >> j & 1 == 1 {
                *s = centre + dz[j];
            }
        }
    }

    pub(super) fn channel_sums<const N: usize>(colors: &[u32; N]) -> [u32; 3] {
        colors.iter().fold([0; 3], |[r, g, b], &c| [r + (c >> 16 & 0xff), g + (c >> 8 & 0xff), b + (c & 0xff)])
    }
}

/// Four samples at a time in SSE2's 128-bit registers.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
mod sse2 {
    use std::arch::x86_64::{
        __m128, __m128i, _mm_add_epi64, _mm_add_ps, _mm_and_ps, _mm_and_si128, _mm_andnot_ps, _mm_andnot_si128,
        _mm_castsi128_ps, _mm_cmpeq_epi32, _mm_cmpgt_epi32, _mm_cmpgt_ps, _mm_movemask_ps, _mm_or_ps, _mm_or_si128,
        _mm_sad_epu8, _mm_set_epi32, _mm_set1_epi32, _mm_set1_ps, _mm_setzero_si128,
    };

    /// Lane `i` of the mask of four samples' bits `bits` (bit `i` for lane `i`): all ones where set.
    #[inline]
    #[target_feature(enable = "sse2")]
    fn lanes(bits: u16) -> __m128i {
        let one_bit = _mm_set_epi32(8, 4, 2, 1);
        _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(i32::from(bits & 0xf)), one_bit), one_bit)
    }

    #[inline]
    #[target_feature(enable = "sse2")]
    pub(super) fn within<const N: usize>(l: &[i32; N], r: &[i32; N], x: i32) -> u16 {
        let xv = _mm_set1_epi32(x);
        let mut m = 0u16;
        for (i, (l, r)) in l.as_chunks::<4>().0.iter().zip(r.as_chunks::<4>().0).enumerate() {
            let (l, r): (__m128i, __m128i) = (bytemuck::cast(*l), bytemuck::cast(*r));
            // l <= x < r: not (l > x), and r > x.
            let inside = _mm_andnot_si128(_mm_cmpgt_epi32(l, xv), _mm_cmpgt_epi32(r, xv));
            m |= (_mm_movemask_ps(_mm_castsi128_ps(inside)) as u16) << (4 * i);
        }
        m
    }

    #[inline]
    #[target_feature(enable = "sse2")]
    pub(super) fn nearer<const N: usize>(mask: u16, centre: f32, dz: &[f32; N], old: &[f32; N]) -> u16 {
        let c = _mm_set1_ps(centre);
        let mut m = 0u16;
        for (i, (dz, old)) in dz.as_chunks::<4>().0.iter().zip(old.as_chunks::<4>().0).enumerate() {
            let (dz, old): (__m128, __m128) = (bytemuck::cast(*dz), bytemuck::cast(*old));
            m |= (_mm_movemask_ps(_mm_cmpgt_ps(_mm_add_ps(c, dz), old)) as u16) << (4 * i);
        }
        m & mask
    }

    #[inline]
    #[target_feature(enable = "sse2")]
    pub(super) fn write_colour<const N: usize>(colors: &mut [u32; N], pass: u16, c: u32) {
        let cv = _mm_set1_epi32(c as i32);
        for (i, s) in colors.as_chunks_mut::<4>().0.iter_mut().enumerate() {
            let m = lanes(pass >> (4 * i));
            let old: __m128i = bytemuck::cast(*s);
            *s = bytemuck::cast(_mm_or_si128(_mm_and_si128(m, cv), _mm_andnot_si128(m, old)));
        }
    }

    #[inline]
    #[target_feature(enable = "sse2")]
    pub(super) fn write_depth<const N: usize>(depths: &mut [f32; N], pass: u16, centre: f32, dz: &[f32; N]) {
        let c = _mm_set1_ps(centre);
        for (i, (s, dz)) in depths.as_chunks_mut::<4>().0.iter_mut().zip(dz.as_chunks::<4>().0).enumerate() {
            let m = _mm_castsi128_ps(lanes(pass >> (4 * i)));
            let (old, dz): (__m128, __m128) = (bytemuck::cast(*s), bytemuck::cast(*dz));
            *s = bytemuck::cast(_mm_or_ps(_mm_and_ps(m, _mm_add_ps(c, dz)), _mm_andnot_ps(m, old)));
        }
    }

    #[inline]
    #[target_feature(enable = "sse2")]
    pub(super) fn channel_sums<const N: usize>(colors: &[u32; N]) -> [u32; 3] {
        // Each channel masked out of four colours, its bytes summed per 64-bit half by `psadbw` against zero.
        let zero = _mm_setzero_si128();
        let channels = [_mm_set1_epi32(0x00ff_0000), _mm_set1_epi32(0x0000_ff00), _mm_set1_epi32(0x0000_00ff)];
        let mut sums = [zero; 3];
        for c in colors.as_chunks::<4>().0 {
            let v: __m128i = bytemuck::cast(*c);
            for (sum, &ch) in sums.iter_mut().zip(&channels) {
                *sum = _mm_add_epi64(*sum, _mm_sad_epu8(_mm_and_si128(v, ch), zero));
            }
        }
        sums.map(|s| {
            let [lo, _, hi, _]: [u32; 4] = bytemuck::cast(s);
            lo + hi
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::test_rng::Lcg;

    /// Every operation against its portable reference on random lanes, for `N` samples.
    fn agree<const N: usize>(rng: &mut Lcg) {
        for _ in 0..2000 {
            let mut ints = || std::array::from_fn::<i32, N, _>(|_| rng.range(-6, 7));
            let (l, r) = (ints(), ints());
            let x = rng.range(-3, 4);
            assert_eq!(within(&l, &r, x), portable::within(&l, &r, x), "{N} samples: within {l:?} {r:?}");
            // Depths on a coarse grid so that ties occur; a NaN now and then, which passes nothing.
            let mut grid = || std::array::from_fn::<f32, N, _>(|_| rng.range(-4, 5) as f32 * 0.25);
            let (dz, mut old) = (grid(), grid());
            if rng.range(0, 4) == 0 {
                old[rng.range(0, N as i32) as usize] = f32::NAN;
            }
            let (mask, pass) = (rng.range(0, 1 << N) as u16, rng.range(0, 1 << N) as u16);
            let centre = rng.range(-4, 5) as f32 * 0.125;
            assert_eq!(nearer(mask, centre, &dz, &old), portable::nearer(mask, centre, &dz, &old));
            let (mut a, mut b) = (old, old);
            write_depth(&mut a, pass, centre, &dz);
            portable::write_depth(&mut b, pass, centre, &dz);
            assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "{N} samples: depths for pass {pass:#x}");
            let mut colors = || std::array::from_fn::<u32, N, _>(|_| rng.next() & 0x00ff_ffff);
            let (mut a, c) = (colors(), rng.next() & 0x00ff_ffff);
            let mut b = a;
            write_colour(&mut a, pass, c);
            portable::write_colour(&mut b, pass, c);
            assert_eq!(a, b, "{N} samples: colours for pass {pass:#x}");
            assert_eq!(channel_sums(&a), portable::channel_sums(&a));
        }
    }

    #[test]
    fn vector_lanes_match_the_portable_reference() {
        let mut rng = Lcg(5);
        agree::<4>(&mut rng);
        agree::<8>(&mut rng);
        agree::<16>(&mut rng);
    }

    #[test]
    fn white_samples_sum_to_255_each() {
        assert_eq!(channel_sums(&[0x00ff_ffff; 16]), [255 * 16; 3]);
        assert_eq!(portable::channel_sums(&[0x0012_3456; 4]), [0x12 * 4, 0x34 * 4, 0x56 * 4]);
    }
}
