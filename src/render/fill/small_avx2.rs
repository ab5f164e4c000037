//! Narrow small triangles with AVX2: a row's four box columns per instruction (coverage, depth test and
//! writes), with no branch per pixel.
//!
//! Each step repeats [`crate::render::fill::small::fill_flat_narrow`] operation for operation: the edge
//! functions are the same integers (a column's value as a product rather than a sum of steps), the depths
//! the same IEEE operations in the same order, and the test the same ordered compare, so the two give
//! bit-identical frames; a unit test compares them on random triangles over random depths.

use std::arch::x86_64::{
    __m128, __m128i, _CMP_GT_OQ, _mm_add_epi32, _mm_add_ps, _mm_and_ps, _mm_and_si128, _mm_blendv_epi8, _mm_blendv_ps,
    _mm_castps_si128, _mm_castsi128_ps, _mm_cmp_ps, _mm_cmpeq_epi32, _mm_cmpgt_epi32, _mm_movemask_ps, _mm_mul_ps,
    _mm_mullo_epi32, _mm_set1_epi32, _mm_set1_ps, _mm_setr_epi32, _mm_setr_ps, _mm_setzero_si128, _mm_sub_ps,
};

use super::row::{BandPixels, COVERAGE, DEPTH_TEST};
use super::small::{self, NarrowRows, NextFlat, fill_row_pixels};
use crate::render::core::small::{NARROW, SmallTriangle};
use crate::render::simd::Avx2;
use crate::render::simd::x86::{load4, store4};

/// [`super::small::fill_flat_run`] with the AVX2 narrow fill.
pub(crate) fn fill_flat_run<'t, const VIS: u8>(
    _: Avx2,
    first: (&'t SmallTriangle, u32),
    next: &mut impl NextFlat<'t>,
    band: (i32, i32),
    px: &mut BandPixels<'_>,
) -> ((u64, u64), Option<(&'t SmallTriangle, u32)>) {
    // SAFETY: an `Avx2` token exists only when the CPU has AVX2 (`simd::avx2`), all `fill_flat_run_avx2`
    // needs.
    #[allow(unsafe_code)]
    unsafe {
        fill_flat_run_avx2::<VIS>(first, next, band, px)
    }
}

/// [`fill_flat_run`]'s body, compiled for AVX2.
#[target_feature(enable = "avx2")]
fn fill_flat_run_avx2<'t, const VIS: u8>(
    first: (&'t SmallTriangle, u32),
    next: &mut impl NextFlat<'t>,
    band: (i32, i32),
    px: &mut BandPixels<'_>,
) -> ((u64, u64), Option<(&'t SmallTriangle, u32)>) {
    small::fill_flat_run(first, next, band, px, |r, color, px| fill_flat_narrow::<VIS>(r, color, px))
}

/// [`super::small::fill_flat_narrow`] with AVX2; returns `(written, rejected)`.
#[inline]
#[target_feature(enable = "avx2")]
pub(crate) fn fill_flat_narrow<const VIS: u8>(r: &NarrowRows, color: u32, px: &mut BandPixels<'_>) -> (u64, u64) {
    let (mut written, mut rejected) = (0u64, 0u64);
    let columns = _mm_setr_epi32(0, 1, 2, 3);
    // Column k's edge value is the row's value plus k steps; a column outside the box is masked off.
    let edge =
        |i: usize| _mm_add_epi32(_mm_set1_epi32(r.at_row[i]), _mm_mullo_epi32(columns, _mm_set1_epi32(r.step_x[i])));
    let (mut e0, mut e1, mut e2) = (edge(0), edge(1), edge(2));
    let step = |i: usize| _mm_set1_epi32(r.step_y[i]);
    let (s0, s1, s2) = (step(0), step(1), step(2));
    let bits = _mm_setr_epi32(1, 2, 4, 8);
    let in_box = _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(r.column_mask as i32), bits), bits);
    let zero = _mm_setzero_si128();
    let lanes = _mm_setr_ps(0.0, 1.0, 2.0, 3.0);
    let dd = _mm_set1_ps(r.depth_step());
    let fill = _mm_set1_epi32(color as i32);
    for y in r.rows.0..r.rows.1 {
        let inside: __m128i = _mm_and_si128(
            _mm_and_si128(_mm_cmpgt_epi32(e0, zero), _mm_cmpgt_epi32(e1, zero)),
            _mm_and_si128(_mm_cmpgt_epi32(e2, zero), in_box),
        );
        (e0, e1, e2) = (_mm_add_epi32(e0, s0), _mm_add_epi32(e1, s1), _mm_add_epi32(e2, s2));
        let m = _mm_movemask_ps(_mm_castsi128_ps(inside)) as u32;
        if m == 0 {
            continue;
        }
        let first = m.trailing_zeros();
        let d0 = r.run_depth(y, first);
        let row = y as usize - px.y0;
        let at = row * px.width + r.x_start;
        let (Some(c), Some(d)) = (
            px.color.get(at..at + NARROW),
            if VIS == DEPTH_TEST { px.depth.get(at..at + NARROW) } else { Some(&[][..]) },
        ) else {
            let (w, j) = fill_row_pixels::<VIS>(m, d0, r.depth_step(), (row, r.x_start), color, px);
            written += w;
            rejected += j;
            continue;
        };
        let old_c: __m128i = load4(c).unwrap_or(zero);
        let pass = match VIS {
            DEPTH_TEST => {
                let old: __m128 = load4(d).unwrap_or(_mm_set1_ps(0.0));
                // d0 + (k - first) * dd, lane by lane; lanes left of the run are not covered.
                let z = _mm_add_ps(_mm_set1_ps(d0), _mm_mul_ps(_mm_sub_ps(lanes, _mm_set1_ps(first as f32)), dd));
                let pass = _mm_and_ps(_mm_cmp_ps::<_CMP_GT_OQ>(z, old), _mm_castsi128_ps(inside));
                store4(&mut px.depth[at..], _mm_blendv_ps(old, z, pass));
                _mm_castps_si128(pass)
            }
            // The covered pixels not yet drawn, as lanes.
            COVERAGE => {
                let claimed = px.claim(row, r.x_start, m);
                _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(claimed as i32), bits), bits)
            }
            _ => inside,
        };
        store4(&mut px.color[at..], _mm_blendv_epi8(old_c, fill, pass));
        let n = u64::from((_mm_movemask_ps(_mm_castsi128_ps(pass)) as u32).count_ones());
        written += n;
        rejected += u64::from(m.count_ones()) - n;
    }
    (written, rejected)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::fixed::Fx28_4;
    use crate::render::core::small::SmallFrame;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::vertex::{ATTRS, ScreenVertex, signed_area2};
    use crate::render::fill::row::OVERWRITE;

    /// What one version drew: the buffers and the counts.
    type Drawn = (Vec<u32>, Vec<f32>, Vec<u64>, (u64, u64));

    /// The band's colour, depth and coverage before drawing.
    type Start = (Vec<u32>, Vec<f32>, Vec<u64>);

    fn draw(r: &NarrowRows, vis: u8, avx2: bool, (y0, width, words): (usize, usize, usize), start: &Start) -> Drawn {
        let (mut color, mut depth, mut coverage) = start.clone();
        let mut px = BandPixels { y0, width, color: &mut color, depth: &mut depth, coverage: &mut coverage, words };
        let c = 0x00ab_cdef;
        #[allow(unsafe_code)]
        // SAFETY: the test runs the AVX2 versions only when the CPU has AVX2.
        let counts = match (vis, avx2) {
            (DEPTH_TEST, false) => small::fill_flat_narrow::<DEPTH_TEST>(r, c, &mut px),
            (COVERAGE, false) => small::fill_flat_narrow::<COVERAGE>(r, c, &mut px),
            (_, false) => small::fill_flat_narrow::<OVERWRITE>(r, c, &mut px),
            (DEPTH_TEST, true) => unsafe { fill_flat_narrow::<DEPTH_TEST>(r, c, &mut px) },
            (COVERAGE, true) => unsafe { fill_flat_narrow::<COVERAGE>(r, c, &mut px) },
            (_, true) => unsafe { fill_flat_narrow::<OVERWRITE>(r, c, &mut px) },
        };
        (color, depth, coverage, counts)
    }

    #[test]
    fn the_avx2_narrow_fill_equals_the_portable_one_bit_for_bit() {
        if !crate::render::simd::has_avx2() {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        }
        let mut rng = Lcg(11);
        let (width, height) = (23usize, 9usize);
        let (mut compared, mut written, mut rejected, mut at_end) = (0, 0, 0, 0);
        for case in 0..20_000 {
            // Corners near the frame's right edge and last rows too, so boxes are clipped and rows reach
            // the end of the buffers.
            let mut corner = |i: usize, near: Option<&ScreenVertex>| {
                let (x, y) = match near {
                    // Within four pixels of the first corner, for a narrow box.
                    Some(p) => (p.x.0 + rng.range(-60, 60), p.y.0 + rng.range(-60, 60)),
                    None => (rng.range(-24, 23 * 16 + 24), rng.range(-24, 9 * 16 + 24)),
                };
                let mut attrs = [0.0; ATTRS];
                attrs[0] = match case % 5 {
                    _ if case % 97 == 0 && i == 1 => f32::NAN,
                    // A constant depth, equal to some of the old ones: ties must keep the old pixel.
                    0 => 0.25,
                    _ => rng.unit() * 2.0 - 0.5,
                };
                ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs }
            };
            let a = corner(0, None);
            let (b, c) = (corner(1, Some(&a)), corner(2, Some(&a)));
            let v = [a, b, c];
            let frame = SmallFrame::plain(width as i32);
            let Some((t, _)) = SmallTriangle::new::<1>(&v, signed_area2(&v), frame) else { continue };
            let band = if case % 3 == 0 { (0, height as i32) } else { (3, 7) };
            let Some(r) = t.narrow_rows(band) else { continue };
            let y0 = band.0 as usize;
            let n = (band.1 - band.0) as usize * width;
            // Random old depths, some NaN, some equal to what the triangle draws.
            let depth: Vec<f32> = (0..n)
                .map(|_| match rng.below(20) {
                    0 => f32::NAN,
                    1 => 0.25,
                    _ => rng.unit() * 2.0 - 0.5,
                })
                .collect();
            // Random 'already drawn' bits, one word a row (the frame is 23 pixels wide).
            let coverage: Vec<u64> =
                (0..n / width).map(|_| u64::from(rng.next()) << 8 ^ u64::from(rng.next())).collect();
            let start = ((0..n as u32).collect(), depth, coverage);
            for vis in [DEPTH_TEST, OVERWRITE, COVERAGE] {
                let portable = draw(&r, vis, false, (y0, width, 1), &start);
                let fast = draw(&r, vis, true, (y0, width, 1), &start);
                let bits =
                    |d: &Drawn| (d.0.clone(), d.1.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), d.2.clone(), d.3);
                assert_eq!(bits(&fast), bits(&portable), "case {case}, visibility {vis}, {v:?}");
                compared += 1;
                written += portable.3.0;
                rejected += portable.3.1;
            }
            at_end += usize::from(r.rows.1 == band.1 && r.x_start + NARROW > width);
        }
        assert!(compared > 5_000 && written > 10_000 && rejected > 2_000, "{compared} {written} {rejected}");
        assert!(at_end > 50, "only {at_end} triangles reached the end of the buffers");
    }
}
