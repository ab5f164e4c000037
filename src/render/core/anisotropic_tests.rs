use super::*;
use crate::render::core::test_rng::Lcg;

/// Gradients of a pixel at `1/w` = 1, `u` = `v` = 0 whose sides are `x` and `y` texels of a `size`
/// texture.
fn footprint(x: (f32, f32), y: (f32, f32), size: f32) -> TexGradients {
    TexGradients { dx: [0.0, x.0 / size, x.1 / size], dy: [0.0, y.0 / size, y.1 / size] }
}

fn noise_texture(w: u32, h: u32, seed: u64) -> Texture {
    let mut rng = Lcg(seed);
    let Ok(t) = Texture::new(w, h, (0..w * h).map(|_| rng.next() | (rng.next() & 1) << 31).collect()) else {
        panic!("texture")
    };
    t
}

/// The mean over a box (`u0..u1`, `v0..v1` in texture coordinates) of `texture`'s nearest texels, from
/// `n` x `n` samples: the integral the filter approximates, per channel in `0..=255`.
fn integral(texture: &Texture, (u0, u1): (f32, f32), (v0, v1): (f32, f32), n: u32) -> [f64; 4] {
    let mut sum = [0.0f64; 4];
    for j in 0..n {
        for i in 0..n {
            let u = u0 + (u1 - u0) * (i as f32 + 0.5) / n as f32;
            let v = v0 + (v1 - v0) * (j as f32 + 0.5) / n as f32;
            let t = texture.texel(
                floor_i32(u * texture.width() as f32),
                floor_i32(v * texture.height() as f32),
                Sampler::default(),
            );
            for (c, s) in sum.iter_mut().enumerate() {
                *s += f64::from(t >> (8 * c) & 0xff);
            }
        }
    }
    sum.map(|s| s / f64::from(n * n))
}

fn worst_difference(got: u32, want: [f64; 4]) -> f64 {
    (0..4).map(|c| (f64::from(got >> (8 * c) & 0xff) - want[c]).abs()).fold(0.0, f64::max)
}

#[test]
fn the_probe_count_level_and_box_follow_the_footprint() {
    let chain = noise_texture(256, 256, 1);
    // (side along x, side along y), maximum: count, level, radius.
    let cases = [
        ((1.0, 0.0), (0.0, 1.0), 16, 1, 0, [0.5, 0.5]),
        ((4.0, 0.0), (0.0, 4.0), 16, 1, 2, [0.5, 0.5]),
        ((16.0, 0.0), (0.0, 2.0), 16, 8, 1, [0.5, 0.5]),
        ((0.0, 2.0), (16.0, 0.0), 16, 8, 1, [0.5, 0.5]),
        ((16.0, 0.0), (0.0, 2.0), 4, 4, 2, [0.5, 0.25]),
        ((64.0, 0.0), (0.0, 0.0), 8, 8, 3, [0.5, 0.0]),
        ((0.5, 0.0), (0.0, 0.25), 16, 1, 0, [0.25, 0.125]),
        ((3.0, 0.0), (0.0, 0.5), 16, 3, 0, [0.5, 0.25]),
        ((8.0, 8.0), (-1.0, 1.0), 16, 8, 1, [0.5, 0.5]),
        ((2.01, 0.0), (0.0, 1.0), 16, 2, 1, [0.5025 / 2.0, 0.25]),
        ((0.0, 0.0), (0.0, 0.0), 16, 1, 0, [0.0, 0.0]),
        ((1e6, 0.0), (0.0, 1e6), 16, 1, 8, [0.5, 0.5]),
    ];
    for (x, y, max, count, level, radius) in cases {
        let p = probes(&footprint(x, y, 256.0), 1.0, (0.0, 0.0), &chain, max);
        assert_eq!((p.count, p.level), (count, level), "{x:?} {y:?} max {max}");
        for (got, want) in p.radius.iter().zip(radius) {
            assert!((got - want).abs() < 1e-4, "{x:?} {y:?} max {max}: {:?}", p.radius);
        }
    }
    // A broken footprint: the nearest texel.
    for (x, y) in [((f32::NAN, 0.0), (1.0, 0.0)), ((f32::INFINITY, 0.0), (0.0, 1.0)), ((1.0, 0.0), (0.0, f32::NAN))] {
        let p = probes(&footprint(x, y, 256.0), 1.0, (0.0, 0.0), &chain, 16);
        assert_eq!(p, Probes::POINT, "{x:?} {y:?}");
    }
}

#[test]
fn the_level_is_the_first_where_the_box_fits_in_a_texel() {
    for (e, level) in [(0.3, 0), (1.0, 0), (1.0001, 1), (2.0, 1), (2.0001, 2), (8.0, 3), (1000.0, 10), (f32::NAN, 0)] {
        assert_eq!(level_for(e), level, "{e}");
    }
}

#[test]
fn a_box_is_the_nearest_texel_when_small_and_the_mean_under_it_otherwise() {
    let t = noise_texture(16, 8, 2);
    let s = Sampler::default();
    let mut rng = Lcg(9);
    for _ in 0..2000 {
        let (u, v) = (rng.unit() * 3.0 - 1.0, rng.unit() * 3.0 - 1.0);
        let nearest = t.texel(floor_i32(u * 16.0), floor_i32(v * 8.0), s);
        assert_eq!(box_sample(&t, (u, v), [0.0, 0.0], s), nearest, "{u} {v}");
    }
    // A texel-sized box on a texel's centre is that texel; on the edge between two, their even mix.
    assert_eq!(box_sample(&t, (5.5 / 16.0, 2.5 / 8.0), [0.5, 0.5], s), t.texel(5, 2, s));
    assert_eq!(box_sample(&t, (6.0 / 16.0, 2.5 / 8.0), [0.5, 0.5], s), blend(t.texel(5, 2, s), t.texel(6, 2, s), 128));
    // Anywhere: the mean of the texels under the box, within the 1/256 weights' rounding.
    for _ in 0..400 {
        let (u, v) = (rng.unit() * 3.0 - 1.0, rng.unit() * 3.0 - 1.0);
        let r = [rng.unit() * 0.5, rng.unit() * 0.5];
        let want = integral(&t, (u - r[0] / 16.0, u + r[0] / 16.0), (v - r[1] / 8.0, v + r[1] / 8.0), 256);
        let got = box_sample(&t, (u, v), r, s);
        assert!(worst_difference(got, want) <= 2.5, "{u} {v} {r:?}: {got:08x} against {want:?}");
    }
}

#[test]
fn the_probes_of_an_axis_aligned_footprint_are_the_mean_over_it() {
    // Magnified along v, three texels long along u: three probes of one texel by half a texel cover the
    // footprint exactly. And minified 8 by 2 on aligned texels: four probes, each a texel of level 1.
    let t = noise_texture(64, 64, 3);
    let s = Sampler::default();
    let mut rng = Lcg(4);
    for ((x, y), aligned) in [(((3.0, 0.0), (0.0, 0.5)), false), (((8.0, 0.0), (0.0, 2.0)), true)] {
        let g = footprint(x, y, 64.0);
        for _ in 0..300 {
            let (mut u, mut v) = (rng.unit(), rng.unit());
            if aligned {
                // The pixel's centre on an edge of level 1's texels along u and on a centre along v, so each
                // probe's box (two texels square) is one of them.
                (u, v) = ((u * 32.0).floor() / 32.0, ((v * 32.0).floor() + 0.5) / 32.0);
            }
            let p = probes(&g, 1.0, (u, v), &t, 16);
            let (hu, hv) = ((x.0 + y.0) / 128.0, (x.1 + y.1) / 128.0);
            let want = integral(&t, (u - hu, u + hu), (v - hv, v + hv), 256);
            let got = p.sample(&t, (u, v), s);
            // The mean of three or four probes rounds once more, and level 1's texels are rounded means.
            assert!(worst_difference(got, want) <= 2.0, "{x:?} {y:?} at {u} {v}: {got:08x} against {want:?}");
        }
    }
}

#[test]
fn probes_span_the_long_side_evenly_and_their_mean_rounds_per_channel() {
    let chain = noise_texture(64, 64, 5);
    let p = probes(&footprint((8.0, 0.0), (0.0, 2.0), 64.0), 1.0, (0.5, 0.25), &chain, 16);
    assert_eq!(p.count, 4);
    let at: Vec<(f32, f32)> = (0..4).map(|i| p.at(i, (0.5, 0.25))).collect();
    // Steps of 2 texels (1/32) centred on the pixel: -3, -1, +1, +3 texels.
    let expected = [-3.0, -1.0, 1.0, 3.0].map(|d: f32| (0.5 + d / 64.0, 0.25));
    assert_eq!(at, expected.to_vec());
    // The mean of 0x00, 0x01, 0xff, 0xff per channel in each byte: 511 / 4 = 127.75, rounded to 128.
    let texels = [0x0000_0000, 0x0101_0101, 0xffff_ffff, 0xffff_ffff];
    let mut i = 0;
    let mean = p.average((0.5, 0.25), |_, _| {
        i += 1;
        texels[i - 1]
    });
    assert_eq!(mean, 0x8080_8080);
    // Against a channel at a time on random texels, for every count.
    let mut rng = Lcg(3);
    for n in 1..=16u32 {
        let probes = Probes { level: 0, radius: [0.0; 2], count: n, step: [0.01, 0.0] };
        let texels: Vec<u32> = (0..n).map(|_| rng.next() | rng.below(2) << 31).collect();
        let mut k = 0;
        let got = probes.average((0.0, 0.0), |_, _| {
            k += 1;
            texels[k - 1]
        });
        for shift in [0, 8, 16, 24] {
            let sum: u32 = texels.iter().map(|t| t >> shift & 0xff).sum();
            assert_eq!(got >> shift & 0xff, (sum + n / 2) / n, "{n} probes, channel at {shift}");
        }
    }
}
