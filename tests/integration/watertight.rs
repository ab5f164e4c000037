//! Watertightness and fill-rule tests: additive counting over thousands of random fans, tessellations and
//! closed meshes with sub-pixel vertices, checked against an independent edge-function reference.

use crate::common::*;
use glam::{Vec3, Vec4};
use scanline_racer::render::core::fixed::Fx28_4;
use scanline_racer::render::core::samples::SamplePattern;
use scanline_racer::render::core::vertex::{ATTRS, ScreenVertex};
use scanline_racer::render::fill::scanline::fill_spans;
use scanline_racer::render::{Antialias, Method, RenderOptions};

fn sv(p: (i64, i64)) -> ScreenVertex {
    ScreenVertex { x: Fx28_4(p.0 as i32), y: Fx28_4(p.1 as i32), attrs: [0.0; ATTRS] }
}

/// Fills triangles with the renderer's scanline walk, counting writes per pixel.
fn fill_counts(tris: &[[(i64, i64); 3]], w: usize, h: usize) -> Vec<u32> {
    let mut counts = vec![0u32; w * h];
    for t in tris {
        let v: Vec<ScreenVertex> = t.iter().copied().map(sv).collect();
        fill_spans(&v, (0, h as i32), w as i32, |s| {
            for x in s.x0..s.x1 {
                counts[s.y as usize * w + x as usize] += 1;
            }
        });
    }
    counts
}

/// A fan of `n` triangles around a centre, rim points at random sub-pixel positions sorted by angle.
fn random_fan(rng: &mut Rng, w: i64, h: i64) -> Vec<[(i64, i64); 3]> {
    let n = rng.range(4, 24) as usize;
    let c = (rng.range(16 * 8, 16 * (w - 8)), rng.range(16 * 8, 16 * (h - 8)));
    let max_r = rng.range(8, 16 * 40) as f64;
    // Jittered even spacing keeps every gap under half a turn, so the fan tiles a star-shaped polygon.
    let angles: Vec<f64> =
        (0..n).map(|i| (i as f64 + 0.5 * rng.unit() as f64) / n as f64 * std::f64::consts::TAU).collect();
    let rim: Vec<(i64, i64)> = angles
        .iter()
        .map(|a| {
            let r = max_r * (0.2 + 0.8 * rng.unit() as f64);
            (c.0 + (r * libm::cos(*a)).round() as i64, c.1 + (r * libm::sin(*a)).round() as i64)
        })
        .collect();
    (0..n).map(|i| [c, rim[i], rim[(i + 1) % n]]).collect()
}

/// A jittered grid split into triangles along random diagonals: a tiling with no gaps or overlaps.
fn random_grid(rng: &mut Rng, w: i64, h: i64) -> Vec<[(i64, i64); 3]> {
    let (nx, ny) = (rng.range(2, 9) as usize, rng.range(2, 9) as usize);
    let cell = (16 * (w - 4) / nx as i64, 16 * (h - 4) / ny as i64);
    let jitter = |rng: &mut Rng, i: usize, n: usize, c: i64| {
        if i == 0 || i == n { 0 } else { rng.range(-c / 5, c / 5 + 1) }
    };
    let mut pts = vec![vec![(0i64, 0i64); nx + 1]; ny + 1];
    for (j, row) in pts.iter_mut().enumerate() {
        for (i, p) in row.iter_mut().enumerate() {
            *p = (
                32 + i as i64 * cell.0 + jitter(rng, i, nx, cell.0),
                32 + j as i64 * cell.1 + jitter(rng, j, ny, cell.1),
            );
        }
    }
    let mut tris = vec![];
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (pts[j][i], pts[j][i + 1], pts[j + 1][i + 1], pts[j + 1][i]);
            if rng.next_u64() & 1 == 0 {
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            } else {
                tris.push([a, b, d]);
                tris.push([b, c, d]);
            }
        }
    }
    tris
}

#[test]
fn scanline_fill_matches_reference_exactly_on_thousands_of_fans_and_grids() {
    let (w, h) = (96usize, 80usize);
    let mut rng = Rng(0x5eed_0001);
    let mut pixels_checked = 0u64;
    for case in 0..3000 {
        let tris = if case % 2 == 0 {
            random_fan(&mut rng, w as i64, h as i64)
        } else {
            random_grid(&mut rng, w as i64, h as i64)
        };
        let expect = ref_counts(&tris, w, h);
        // The reference itself must see a tiling: no centre in two triangles.
        assert!(expect.iter().all(|&c| c <= 1), "case {case}: reference found an overlap");
        let got = fill_counts(&tris, w, h);
        if got != expect {
            let i = got.iter().zip(&expect).position(|(a, b)| a != b).unwrap_or(0);
            panic!(
                "case {case}: pixel ({}, {}) written {} times, reference {}; triangles {tris:?}",
                i % w,
                i / w,
                got[i],
                expect[i]
            );
        }
        pixels_checked += expect.iter().map(|&c| u64::from(c)).sum::<u64>();
    }
    assert!(pixels_checked > 1_000_000, "too little coverage tested: {pixels_checked}");
}

#[test]
fn vertices_on_pixel_centres_and_edges_follow_the_top_left_rule() {
    // Every coordinate a multiple of half a pixel: every edge passes through pixel centres or corners.
    let (w, h) = (40usize, 40usize);
    let mut rng = Rng(0xce17e5);
    for case in 0..2000 {
        let mut tris = if case % 2 == 0 {
            random_fan(&mut rng, w as i64, h as i64)
        } else {
            random_grid(&mut rng, w as i64, h as i64)
        };
        for t in &mut tris {
            for p in t.iter_mut() {
                *p = ((p.0 / 8) * 8, (p.1 / 8) * 8);
            }
        }
        let expect = ref_counts(&tris, w, h);
        let got = fill_counts(&tris, w, h);
        assert_eq!(got, expect, "case {case}: {tris:?}");
    }
    // Two triangles sharing a diagonal through pixel centres: each centre on it drawn once.
    let quad = [[(8, 8), (328, 8), (328, 328)], [(8, 8), (328, 328), (8, 328)]];
    let got = fill_counts(&quad, 24, 24);
    assert_eq!(got.iter().filter(|&&c| c == 1).count(), 20 * 20);
    assert!(got.iter().all(|&c| c <= 1));
}

#[test]
fn slivers_thinner_than_a_pixel_tile_without_gaps() {
    // A fan of 200 triangles each a fraction of a pixel wide at the rim.
    let (w, h) = (64usize, 64usize);
    let c = (32 * 16 + 3, 32 * 16 + 5);
    let rim: Vec<(i64, i64)> = (0..200)
        .map(|i| {
            let a = i as f64 / 200.0 * std::f64::consts::TAU;
            (c.0 + (400.0 * libm::cos(a)).round() as i64, c.1 + (400.0 * libm::sin(a)).round() as i64)
        })
        .collect();
    let tris: Vec<_> = (0..200).map(|i| [c, rim[i], rim[(i + 1) % 200]]).collect();
    let expect = ref_counts(&tris, w, h);
    assert!(expect.iter().all(|&c| c <= 1));
    assert_eq!(fill_counts(&tris, w, h), expect);
    assert!(expect.iter().filter(|&&c| c == 1).count() > 1500);
}

/// Random convex polyhedron (points on a sphere, hull by brute force), with vertices on the 1/16 grid.
fn random_convex_hull(rng: &mut Rng, w: usize, h: usize) -> Vec<[Vec3; 3]> {
    let n = rng.range(5, 14) as usize;
    let c = Vec3::new(rng.range(16, w as i64 - 16) as f32, rng.range(16, h as i64 - 16) as f32, 0.0);
    let r = rng.range(4, 30) as f32;
    let pts: Vec<Vec3> = (0..n)
        .map(|_| {
            let d = loop {
                let v = Vec3::new(rng.unit() * 2.0 - 1.0, rng.unit() * 2.0 - 1.0, rng.unit() * 2.0 - 1.0);
                if v.length() > 0.2 && v.length() < 1.0 {
                    break v.normalize();
                }
            };
            let p = c + d * r;
            // Snap x and y to the 1/16 grid (exact under the pixel camera); z is free.
            Vec3::new((p.x * 16.0).round() / 16.0, (p.y * 16.0).round() / 16.0, p.z)
        })
        .collect();
    let mut faces = vec![];
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let nrm = (pts[j] - pts[i]).cross(pts[k] - pts[i]);
                if nrm.length() < 1e-3 {
                    continue;
                }
                let side: Vec<f32> =
                    (0..n).filter(|&m| m != i && m != j && m != k).map(|m| nrm.dot(pts[m] - pts[i])).collect();
                if side.iter().any(|s| s.abs() < 1e-3) {
                    return vec![]; // coplanar points: skip this hull
                }
                if side.iter().all(|&s| s < 0.0) {
                    faces.push([pts[i], pts[j], pts[k]]);
                } else if side.iter().all(|&s| s > 0.0) {
                    faces.push([pts[i], pts[k], pts[j]]);
                }
            }
        }
    }
    faces
}

#[test]
fn closed_meshes_are_watertight_in_every_method() {
    let (w, h) = (128usize, 128usize);
    let camera = pixel_camera(w, h);
    let mut rng = Rng(0xc105ed);
    let mut meshes_tested = 0;
    for case in 0..400 {
        let faces = random_convex_hull(&mut rng, w, h);
        if faces.is_empty() {
            continue;
        }
        meshes_tested += 1;
        // Reference: front faces (counter-clockwise seen from +z, i.e. clockwise on screen after the y flip).
        let to_px = |p: Vec3| ((p.x * 16.0) as i64, ((h as f32 - p.y) * 16.0) as i64);
        let screen: Vec<[(i64, i64); 3]> = faces
            .iter()
            .map(|f| [to_px(f[0]), to_px(f[1]), to_px(f[2])])
            .filter(|t| {
                let [a, b, c] = *t;
                (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0) < 0
            })
            .collect();
        let expect = ref_counts(&screen, w, h);
        let covered: u64 = expect.iter().filter(|&&c| c > 0).count() as u64;
        let total: u64 = expect.iter().map(|&c| u64::from(c)).sum();
        assert_eq!(covered, total, "case {case}: front faces of a convex hull overlap in the reference");
        let mesh = tri_mesh(&faces, &[Vec4::new(1.0, 0.0, 0.0, 1.0), Vec4::new(0.0, 1.0, 0.0, 1.0)], false);
        for method in Method::ALL {
            let opts = RenderOptions { method, background: Some(0), threads: 1 + case % 3, ..RenderOptions::default() };
            let (frame, stats) = render(std::slice::from_ref(&mesh), &[], &camera, w, h, &opts);
            assert_eq!(stats.pixels_written, total, "case {case} {method}: pixels written");
            for i in 0..w * h {
                assert_eq!(frame[i] != 0, expect[i] > 0, "case {case} {method}: pixel ({}, {})", i % w, i / w);
            }
        }
    }
    assert!(meshes_tested > 300, "only {meshes_tested} hulls tested");
}

/// The front faces of a random convex hull as screen triangles (1/16 pixel, y down) under `pixel_camera`.
fn front_faces(faces: &[[Vec3; 3]], h: usize) -> Vec<[(i64, i64); 3]> {
    let to_px = |p: Vec3| ((p.x * 16.0) as i64, ((h as f32 - p.y) * 16.0) as i64);
    faces
        .iter()
        .map(|f| [to_px(f[0]), to_px(f[1]), to_px(f[2])])
        .filter(|t| {
            let [a, b, c] = *t;
            (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0) < 0
        })
        .collect()
}

#[test]
fn closed_meshes_are_watertight_under_every_anti_aliasing_and_method() {
    // A white hull over black: each pixel must come out exactly as the share of its samples that the
    // reference edge functions put inside the hull (resolved with rounding to nearest), so a sample lost at
    // a shared edge (background through a seam) or drawn twice shows as a wrong level.
    let (w, h) = (64usize, 64usize);
    let camera = pixel_camera(w, h);
    let mut rng = Rng(0x5a3b1e);
    let ssaa: Vec<(i64, i64)> = vec![(4, 4), (12, 4), (4, 12), (12, 12)];
    // The rotated grid's samples: each pass shifts the image by (-2, -6), (6, -2), (-6, 2) and (2, 6)
    // sixteenths, so the pixel centre (8, 8) sees the scene at the opposite offsets.
    let rgss: Vec<(i64, i64)> = vec![(10, 14), (2, 10), (14, 6), (6, 2)];
    let mut tested = 0;
    for case in 0..60 {
        let faces = random_convex_hull(&mut rng, w, h);
        if faces.is_empty() {
            continue;
        }
        tested += 1;
        let screen = front_faces(&faces, h);
        let mesh = tri_mesh(&faces, &[Vec4::ONE], false);
        // Every anti-aliasing choice.
        for aa in Antialias::ALL.into_iter().filter(|&a| a != Antialias::Off) {
            let samples: Vec<(i64, i64)> = match aa.coverage_samples().and_then(SamplePattern::standard) {
                Some(p) => p.positions[..p.count].iter().map(|&(x, y)| (i64::from(x), i64::from(y))).collect(),
                None if aa == Antialias::RotatedGrid => rgss.clone(),
                None => ssaa.clone(),
            };
            let n = samples.len() as u32;
            let expect: Vec<u32> = (0..w * h)
                .map(|i| {
                    let (px, py) = ((i % w) as i64, (i / w) as i64);
                    let inside = samples
                        .iter()
                        .map(|&(sx, sy)| {
                            screen.iter().filter(|t| ref_covers_point(**t, (px * 16 + sx, py * 16 + sy))).count()
                        })
                        .inspect(|&c| assert!(c <= 1, "case {case}: front faces overlap in the reference"))
                        .sum::<usize>() as u32;
                    (255 * inside + n / 2) / n
                })
                .collect();
            for method in [Method::ZBuffer, Method::BucketNear, Method::BucketFar] {
                let threads = 1 + case % 3;
                let opts =
                    RenderOptions { method, antialias: aa, background: Some(0), threads, ..RenderOptions::default() };
                let (frame, _) = render(std::slice::from_ref(&mesh), &[], &camera, w, h, &opts);
                for i in 0..w * h {
                    assert_eq!(
                        frame[i] >> 16 & 0xff,
                        expect[i],
                        "case {case} {method} aa {aa}: pixel ({}, {})",
                        i % w,
                        i / w
                    );
                }
            }
        }
    }
    assert!(tested > 40, "only {tested} hulls tested");
}
