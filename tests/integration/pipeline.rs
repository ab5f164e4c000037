//! Pipeline behaviour: hostile coordinates, near-plane crossings, non-monotone polygons, method agreement,
//! thread-count determinism, masks and texture modes.

use crate::common::*;
use glam::{Mat4, Vec2, Vec3, Vec4};
use scanline_racer::render::{
    AlphaMode, Antialias, Camera, DrawList, Filter, Instance, Material, MeshBuilder, Method, RenderOptions, Renderer,
    Texture, TextureMode, Vertex, Wrap,
};

const RED: Vec4 = Vec4::new(1.0, 0.0, 0.0, 1.0);
const GREEN: Vec4 = Vec4::new(0.0, 1.0, 0.0, 1.0);
const BLUE: Vec4 = Vec4::new(0.0, 0.0, 1.0, 1.0);

fn opts(method: Method) -> RenderOptions {
    RenderOptions { method, background: Some(0), ..RenderOptions::default() }
}

#[test]
fn nan_inf_and_huge_vertices_never_panic_and_are_counted() {
    let (w, h) = (64usize, 48usize);
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.0, 0.1, Some(100.0));
    let bad = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e30, -1e30, 1e6, -1e6, f32::MAX, f32::MIN_POSITIVE];
    let mut tris = vec![];
    for &b in &bad {
        tris.push([Vec3::new(b, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)]);
        tris.push([Vec3::new(0.0, b, 0.0), Vec3::new(1.0, b, 0.0), Vec3::new(0.0, 1.0, b)]);
        tris.push([Vec3::splat(b), Vec3::splat(b), Vec3::splat(b)]);
    }
    let mesh = tri_mesh(&tris, &[RED], true);
    for method in Method::ALL {
        for mode in [TextureMode::Perspective, TextureMode::Subdivided, TextureMode::Affine] {
            let o = RenderOptions { texture_mode: mode, ..opts(method) };
            let (_, stats) = render(std::slice::from_ref(&mesh), &[], &camera, w, h, &o);
            assert_eq!(stats.polygons_in, tris.len() as u64);
            // NaN and infinity in a vertex drop the polygon and are counted; nothing is lost silently.
            assert!(stats.polygons_invalid >= 6, "{method}: {stats:?}");
            let accounted = stats.polygons_invalid
                + stats.polygons_outside
                + stats.polygons_backface
                + stats.polygons_degenerate
                + stats.polygons_drawn
                + stats.polygons_in_culled_objects;
            assert_eq!(accounted, stats.polygons_in, "{method}: {stats:?}");
        }
    }
    // A NaN model matrix or camera: everything is dropped, no panic.
    let mut frame = vec![0u32; w * h];
    let list_meshes = [mesh];
    let nan = Instance::new(0, Mat4::from_scale(Vec3::splat(f32::NAN)));
    let missing = Instance::new(7, Mat4::IDENTITY);
    let list =
        DrawList { meshes: &list_meshes, textures: &[], instances: &[nan, missing], lod_sets: &[], view_lists: None };
    let stats = Renderer::new().render(&mut frame, w, h, &camera, &list, &opts(Method::ZBuffer)).unwrap();
    assert_eq!(stats.pixels_written, 0);
    let nan_cam = Camera::look_at(Vec3::splat(f32::NAN), Vec3::ZERO, 1.0, 0.1, None);
    let stats = Renderer::new().render(&mut frame, w, h, &nan_cam, &list, &opts(Method::BucketNear)).unwrap();
    assert_eq!(stats.pixels_written, 0);
}

#[test]
fn huge_but_finite_polygons_are_clipped_to_the_guard_band_and_still_cover_the_frame() {
    let (w, h) = (80usize, 60usize);
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.0, 0.1, None);
    // One triangle far larger than the view, in front of the camera, covering the whole frame.
    let t = [Vec3::new(-1e6, -1e6, 0.0), Vec3::new(1e6, -1e6, 0.0), Vec3::new(0.0, 1e6, 0.0)];
    let mesh = tri_mesh(&[t], &[GREEN], true);
    for method in Method::ALL {
        let (frame, stats) = render(std::slice::from_ref(&mesh), &[], &camera, w, h, &opts(method));
        assert_eq!(stats.polygons_clipped, 1);
        assert_eq!(stats.pixels_written, (w * h) as u64, "{method}");
        assert!(frame.iter().all(|&p| p == 0x00ff00));
    }
}

#[test]
fn zero_sized_and_short_frames() {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.0, 0.1, None);
    let mesh = tri_mesh(&[[Vec3::ZERO, Vec3::X, Vec3::Y]], &[RED], true);
    let meshes = [mesh];
    let instances = [Instance::new(0, Mat4::IDENTITY)];
    let list = DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
    let mut r = Renderer::new();
    let stats = r.render(&mut [], 0, 0, &camera, &list, &RenderOptions::default()).unwrap();
    assert_eq!(stats.pixels_written, 0);
    let stats = r.render(&mut [], 0, 100, &camera, &list, &RenderOptions::default()).unwrap();
    assert_eq!(stats.pixels_written, 0);
    assert!(r.render(&mut [0; 10], 4, 4, &camera, &list, &RenderOptions::default()).is_err());
    // 1x1 works.
    let mut one = [0u32];
    r.render(&mut one, 1, 1, &camera, &list, &RenderOptions::default()).unwrap();
}

#[test]
fn near_plane_crossing_ground_is_cut_not_dropped_and_behind_is_dropped() {
    let (w, h) = (64usize, 64usize);
    // Eye 1 above a ground plane looking along -Z and slightly down; the ground runs from behind the
    // camera to far ahead, so it crosses the near plane.
    let camera = Camera {
        view: glam::camera::rh::view::look_to_mat4(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -0.3, -1.0), Vec3::Y),
        projection: scanline_racer::render::Projection::Perspective { yfov: 1.2, aspect: None, znear: 0.5, zfar: None },
    };
    let ground = [
        [Vec3::new(-50.0, 0.0, 20.0), Vec3::new(50.0, 0.0, 20.0), Vec3::new(50.0, 0.0, -500.0)],
        [Vec3::new(-50.0, 0.0, 20.0), Vec3::new(50.0, 0.0, -500.0), Vec3::new(-50.0, 0.0, -500.0)],
    ];
    let behind = [Vec3::new(-1.0, 0.0, 5.0), Vec3::new(1.0, 0.0, 5.0), Vec3::new(0.0, 2.0, 5.0)];
    let mesh = tri_mesh(&[ground[0], ground[1], behind], &[GREEN, GREEN, RED], true);
    for method in Method::ALL {
        let (frame, stats) = render(std::slice::from_ref(&mesh), &[], &camera, w, h, &opts(method));
        assert_eq!(stats.polygons_clipped, 2, "{method}: {stats:?}");
        assert_eq!(stats.polygons_outside, 1, "{method}: the triangle behind the eye is rejected");
        // The bottom rows (looking down at the ground right in front of the eye) are all ground.
        for y in h - 8..h {
            assert!((0..w).all(|x| frame[y * w + x] == 0x00ff00), "{method}: row {y} not filled");
        }
        // The horizon: top rows see the sky.
        assert!((0..w).all(|x| frame[x] == 0), "{method}: top row should be background");
        assert!(frame.iter().all(|&p| p == 0 || p == 0x00ff00));
    }
}

#[test]
fn non_monotone_polygon_renders_like_its_triangulation() {
    let (w, h) = (128usize, 128usize);
    let camera = pixel_camera(w, h);
    // A 'U' and a five-pointed star as single polygons (planar, not y-monotone), vertices off the grid.
    let u: Vec<Vec2> = [
        (10.3, 10.1),
        (30.7, 10.2),
        (30.6, 50.9),
        (60.2, 50.4),
        (60.5, 10.8),
        (80.1, 10.3),
        (80.9, 80.2),
        (10.4, 80.6),
    ]
    .iter()
    .map(|&(x, y)| Vec2::new(x, y))
    .collect();
    let star: Vec<Vec2> = (0..10)
        .map(|i| {
            let a = i as f32 * std::f32::consts::PI / 5.0 + 0.3;
            let r = if i % 2 == 0 { 40.0 } else { 15.0 };
            Vec2::new(64.0 + r * libm::cosf(a), 64.0 + r * libm::sinf(a))
        })
        .collect();
    for (name, outline) in [("U", &u), ("star", &star)] {
        let mut b = MeshBuilder::new();
        let m = b.material(Material { double_sided: true, ..Material::default() });
        let idx: Vec<u32> = outline
            .iter()
            .map(|p| b.vertex(Vertex { position: Vec3::new(p.x, p.y, 0.0), uv: Vec2::ZERO, color: BLUE }))
            .collect();
        b.polygon(&idx, m);
        let whole = b.build().unwrap();
        assert_eq!(whole.polygons().len(), 1, "{name}: planar polygon kept whole");
        // Its triangulation by ear clipping in the test (independent of the renderer's).
        let tris = ear_clip(outline);
        let tri_mesh = tri_mesh(
            &tris.iter().map(|t| [t[0].extend(0.0), t[1].extend(0.0), t[2].extend(0.0)]).collect::<Vec<_>>(),
            &[BLUE],
            true,
        );
        let (a, sa) = render(std::slice::from_ref(&whole), &[], &camera, w, h, &opts(Method::ZBuffer));
        let (b_img, sb) = render(std::slice::from_ref(&tri_mesh), &[], &camera, w, h, &opts(Method::ZBuffer));
        assert_eq!(sa.polygons_split, 1, "{name}: detected as not y-monotone");
        assert_eq!(sa.pixels_written, sb.pixels_written, "{name}");
        assert!(a == b_img, "{name}: images differ");
        assert!(sa.pixels_written > 500);
    }
}

#[test]
fn convex_polygons_of_any_vertex_count_are_filled_whole() {
    let (w, h) = (128usize, 128usize);
    let camera = pixel_camera(w, h);
    for n in [4usize, 5, 8, 17, 64] {
        let outline: Vec<Vec2> = (0..n)
            .map(|i| {
                let a = i as f32 / n as f32 * std::f32::consts::TAU + 0.1;
                Vec2::new(64.3 + 50.0 * libm::cosf(a), 63.7 + 45.0 * libm::sinf(a))
            })
            .collect();
        let mut b = MeshBuilder::new();
        let m = b.material(Material { double_sided: true, ..Material::default() });
        let idx: Vec<u32> = outline
            .iter()
            .map(|p| b.vertex(Vertex { position: p.extend(0.0), uv: Vec2::ZERO, color: GREEN }))
            .collect();
        b.polygon(&idx, m);
        let whole = b.build().unwrap();
        let fan: Vec<[Vec3; 3]> =
            (1..n - 1).map(|k| [outline[0].extend(0.0), outline[k].extend(0.0), outline[k + 1].extend(0.0)]).collect();
        let fan = tri_mesh(&fan, &[GREEN], true);
        let (a, sa) = render(std::slice::from_ref(&whole), &[], &camera, w, h, &opts(Method::BucketFar));
        let (b_img, sb) = render(std::slice::from_ref(&fan), &[], &camera, w, h, &opts(Method::BucketFar));
        assert_eq!((sa.polygons_drawn, sa.pieces_filled, sa.polygons_split), (1, 1, 0), "{n}-gon filled as one piece");
        assert_eq!(sa.pixels_written, sb.pixels_written, "{n}-gon: same pixels as its fan");
        assert!(a == b_img, "{n}-gon differs from its fan");
    }
}

/// Plain O(n^3) ear clipping in floating point, for the test only.
fn ear_clip(poly: &[Vec2]) -> Vec<[Vec2; 3]> {
    let area: f32 = (0..poly.len()).map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()])).sum();
    let mut rest: Vec<Vec2> = poly.to_vec();
    let mut out = vec![];
    while rest.len() > 3 {
        let n = rest.len();
        let k = (0..n)
            .find(|&k| {
                let (a, b, c) = (rest[(k + n - 1) % n], rest[k], rest[(k + 1) % n]);
                (b - a).perp_dot(c - b) * area > 0.0
                    && !rest.iter().any(|&p| {
                        p != a && p != b && p != c && {
                            let s = |u: Vec2, v: Vec2| (v - u).perp_dot(p - u) * area;
                            s(a, b) >= 0.0 && s(b, c) >= 0.0 && s(c, a) >= 0.0
                        }
                    })
            })
            .expect("an ear");
        out.push([rest[(k + n - 1) % n], rest[k], rest[(k + 1) % n]]);
        rest.remove(k);
    }
    out.push([rest[0], rest[1], rest[2]]);
    out
}

/// Three slabs at distinct depths overlapping on screen, submitted far, near, middle.
fn layered_scene() -> (Vec<scanline_racer::render::Mesh>, Camera) {
    let quad = |x: f32, y: f32, z: f32| {
        [
            [Vec3::new(x, y, z), Vec3::new(x + 2.0, y, z), Vec3::new(x + 2.0, y + 2.0, z)],
            [Vec3::new(x, y, z), Vec3::new(x + 2.0, y + 2.0, z), Vec3::new(x, y + 2.0, z)],
        ]
    };
    let mut tris = vec![];
    let mut colors = vec![];
    for (q, c) in [(quad(-1.5, -1.5, -2.0), RED), (quad(-0.5, -0.5, 1.0), BLUE), (quad(-1.0, -1.0, -0.5), GREEN)] {
        tris.extend_from_slice(&q);
        colors.extend_from_slice(&[c, c]);
    }
    let mut b = MeshBuilder::new();
    let m = b.material(Material::default());
    for (t, c) in tris.iter().zip(&colors) {
        let idx: Vec<u32> = t.iter().map(|&p| b.vertex(Vertex { position: p, uv: Vec2::ZERO, color: *c })).collect();
        b.polygon(&idx, m);
    }
    (vec![b.build().unwrap()], Camera::look_at(Vec3::new(0.3, 0.2, 6.0), Vec3::ZERO, 1.0, 0.5, Some(50.0)))
}

#[test]
fn all_methods_agree_on_separated_layers_and_bucket_near_shades_once() {
    let (w, h) = (96usize, 72usize);
    let (meshes, camera) = layered_scene();
    let (reference, zs) = render(&meshes, &[], &camera, w, h, &opts(Method::ZBuffer));
    for method in [Method::Sort, Method::BucketFar, Method::BucketNear] {
        for buckets in [1usize, 2, 8, 1024] {
            let o = RenderOptions { buckets, ..opts(method) };
            let (img, stats) = render(&meshes, &[], &camera, w, h, &o);
            if method == Method::Sort || buckets >= 8 {
                assert!(img == reference, "{method} with {buckets} buckets differs from the z-buffer");
            }
            if method == Method::BucketNear {
                // Front to back with coverage: every covered pixel shaded exactly once.
                assert_eq!(stats.pixels_shaded, stats.pixels_written);
                let covered = img.iter().filter(|&&p| p != 0).count() as u64;
                assert_eq!(stats.pixels_written, covered);
            } else {
                assert!(stats.pixels_written > zs.pixels_written || buckets < 8 || method == Method::ZBuffer);
            }
        }
    }
    // Painter's methods overdraw; the z-buffer rejects the hidden layers before shading them.
    let (_, far) = render(&meshes, &[], &camera, w, h, &opts(Method::BucketFar));
    assert!(far.pixels_written > zs.pixels_written);
    assert!(zs.pixels_rejected > 0);
}

#[test]
fn frames_are_bit_identical_for_every_thread_count() {
    let path = samples().join("Duck/Duck.gltf");
    let scene = scanline_racer::asset::load(&path).expect("Duck loads");
    let (w, h) = (203usize, 157usize);
    let camera = scene.framing_camera(w as f32 / h as f32);
    for method in Method::ALL {
        for mode in [TextureMode::Perspective, TextureMode::Subdivided] {
            let mut first: Option<Vec<u32>> = None;
            for threads in [1usize, 2, 3, 4, 7, 16, 157, 400] {
                let o = RenderOptions {
                    method,
                    threads,
                    texture_mode: mode,
                    filter: Filter::Bilinear,
                    ..RenderOptions::default()
                };
                let mut frame = vec![0u32; w * h];
                Renderer::new().render(&mut frame, w, h, &camera, &scene.draw_list(), &o).unwrap();
                match &first {
                    None => first = Some(frame),
                    Some(f) => assert!(*f == frame, "{method} {mode:?}: {threads} threads differ from 1"),
                }
            }
        }
    }
}

#[test]
fn anti_aliased_frames_are_bit_identical_for_every_thread_count() {
    let path = samples().join("Duck/Duck.gltf");
    let scene = scanline_racer::asset::load(&path).expect("Duck loads");
    let (w, h) = (203usize, 157usize);
    let camera = scene.framing_camera(w as f32 / h as f32);
    let draw = |method, antialias, threads| {
        let o = RenderOptions { method, threads, antialias, ..RenderOptions::default() };
        let mut frame = vec![0u32; w * h];
        Renderer::new().render(&mut frame, w, h, &camera, &scene.draw_list(), &o).unwrap();
        frame
    };
    for method in Method::ALL {
        let plain = draw(method, Antialias::Off, 1);
        // Every anti-aliasing choice.
        for aa in Antialias::ALL.into_iter().filter(|&a| a != Antialias::Off) {
            let first = draw(method, aa, 1);
            // Anti-aliasing changes the edges (some thousands of pixels of the duck's outline and its
            // polygons' seams) and keeps the inside: most pixels stay as they were.
            let changed = first.iter().zip(&plain).filter(|(a, b)| a != b).count();
            assert!(changed > 200 && changed < w * h / 3, "{method} {aa}: {changed} pixels changed");
            for threads in [2usize, 3, 7, 157] {
                assert!(draw(method, aa, threads) == first, "{method} {aa}: {threads} threads differ from 1");
            }
        }
    }
}

/// 2x2 supersampling and the rotated grid draw each band into rows each thread keeps from band to band and
/// frame to frame without clearing them: a renderer reused across sizes, thread counts, backgrounds (drawn
/// over noise when there is none) and the two draws what a fresh one draws.
#[test]
fn a_supersampling_renderer_reused_across_sizes_and_backgrounds_draws_what_a_fresh_one_draws() {
    let scene = scanline_racer::asset::load(&samples().join("Duck/Duck.gltf")).expect("Duck loads");
    let mut reused = Renderer::new();
    let mut seed = 1u32;
    for (i, (w, h, background, threads)) in
        [(64usize, 48usize, true, 1usize), (40, 30, false, 2), (80, 60, true, 3), (64, 48, false, 1), (33, 17, true, 2)]
            .into_iter()
            .cycle()
            .take(10)
            .enumerate()
    {
        let camera = scene.framing_camera(w as f32 / h as f32);
        let o = RenderOptions {
            antialias: if i % 3 == 1 { Antialias::RotatedGrid } else { Antialias::Supersample2x2 },
            threads,
            background: if background { RenderOptions::default().background } else { None },
            ..RenderOptions::default()
        };
        // What is there before the drawing: noise, which shows where nothing is drawn without a background.
        let noise: Vec<u32> = (0..w * h)
            .map(|_| {
                seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                seed >> 8
            })
            .collect();
        let (mut a, mut b) = (noise.clone(), noise.clone());
        reused.render(&mut a, w, h, &camera, &scene.draw_list(), &o).unwrap();
        Renderer::new().render(&mut b, w, h, &camera, &scene.draw_list(), &o).unwrap();
        assert!(a == b, "{w}x{h}, background {background}, {threads} threads: the reused renderer differs");
        let kept = a.iter().zip(&noise).filter(|(p, q)| p == q).count();
        assert_eq!(kept > w * h / 4, !background, "{w}x{h}: {kept} pixels of the noise kept");
    }
}

/// Several big objects in one frame each set up in pieces on the pool, their screen vertices left in their
/// own set-up batches: frames must not depend on the thread count, and a renderer reused across frames
/// with different object counts must draw the same as a fresh one.
#[test]
fn frames_with_several_big_objects_are_bit_identical_for_every_thread_count() {
    let path = samples().join("Duck/Duck.gltf");
    let mut scene = scanline_racer::asset::load(&path).expect("Duck loads");
    let (w, h) = (160usize, 120usize);
    let camera = scene.framing_camera(w as f32 / h as f32);
    let duck = scene.instances[0];
    let (lo, hi) = scene.bounds.expect("the duck has bounds");
    let size = (hi - lo).length();
    // Four ducks side by side and in depth, overlapping on screen.
    for k in 1..4 {
        let mut d = duck;
        d.model = Mat4::from_translation(Vec3::new(0.3 * k as f32, 0.0, -0.4 * k as f32) * size) * d.model;
        scene.instances.push(d);
    }
    let polygons: usize = scene.meshes.iter().map(|m| m.polygons().len()).sum();
    assert!(polygons >= 1024, "each duck must be big enough to be set up in pieces ({polygons} polygons)");
    let render_with = |r: &mut Renderer, instances: usize, threads: usize, method: Method| {
        let list = DrawList { instances: &scene.instances[..instances], ..scene.draw_list() };
        let mut frame = vec![0u32; w * h];
        let o = RenderOptions { method, threads, ..RenderOptions::default() };
        let stats = r.render(&mut frame, w, h, &camera, &list, &o).unwrap();
        (frame, stats.polygons_drawn)
    };
    for method in Method::ALL {
        let reference = render_with(&mut Renderer::new(), 4, 1, method);
        let one = render_with(&mut Renderer::new(), 1, 1, method);
        assert!(reference.1 > one.1, "{method}: four ducks draw more polygons than one");
        for threads in [2usize, 3, 5] {
            let mut r = Renderer::new();
            assert!(render_with(&mut r, 4, threads, method) == reference, "{method}: {threads} threads differ from 1");
            // Fewer objects, then more again, on the same renderer.
            assert!(render_with(&mut r, 1, threads, method) == one, "{method}: {threads} threads, one duck after four");
            assert!(render_with(&mut r, 4, threads, method) == reference, "{method}: {threads} threads, reused");
        }
    }
}

fn checker(n: u32) -> Texture {
    let texels =
        (0..n * n).map(|i| if ((i % n) + (i / n)).is_multiple_of(2) { 0xffff_ffff } else { 0xff00_0000 }).collect();
    Texture::new(n, n, texels).unwrap()
}

/// A textured floor quad seen at a grazing angle, uv 0..4 with REPEAT.
fn floor(material: Material) -> scanline_racer::render::Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(material);
    let corners = [(-4.0, 0.0, 0.0, 4.0), (4.0, 0.0, 4.0, 4.0), (4.0, -40.0, 4.0, 0.0), (-4.0, -40.0, 0.0, 0.0)];
    let idx: Vec<u32> = corners
        .iter()
        .map(|&(x, z, u, v)| b.vertex(Vertex { position: Vec3::new(x, 0.0, z), uv: Vec2::new(u, v), color: Vec4::ONE }))
        .collect();
    b.polygon(&idx, m);
    b.build().unwrap()
}

#[test]
fn texture_modes_differ_as_expected_and_subdivided_is_closer_than_affine() {
    let (w, h) = (160usize, 120usize);
    let camera = Camera::look_at(Vec3::new(0.0, 1.0, 2.0), Vec3::new(0.0, 0.0, -8.0), 1.0, 0.1, None);
    let mesh = floor(Material { texture: Some(0), double_sided: true, ..Material::default() });
    let tex = [checker(8)];
    let run = |mode| {
        render(
            std::slice::from_ref(&mesh),
            &tex,
            &camera,
            w,
            h,
            &RenderOptions { texture_mode: mode, ..opts(Method::ZBuffer) },
        )
        .0
    };
    let (p, s, a) = (run(TextureMode::Perspective), run(TextureMode::Subdivided), run(TextureMode::Affine));
    let wrong = |x: &[u32]| x.iter().zip(&p).filter(|(a, b)| channel_diff(**a, **b) > 8).count();
    let (ws, wa) = (wrong(&s), wrong(&a));
    assert!(wa > 1000, "affine should warp visibly: {wa}");
    assert!(ws * 10 < wa, "subdivided ({ws}) should be far closer than affine ({wa})");
    // The floor covers the same pixels whatever the mode.
    assert_eq!(p.iter().filter(|&&x| x != 0).count(), a.iter().filter(|&&x| x != 0).count());
}

#[test]
fn alpha_mask_cuts_holes_and_coverage_lets_the_background_through() {
    let (w, h) = (64usize, 64usize);
    let camera = pixel_camera(w, h);
    // Front quad: texture with transparent left half; behind it a red quad.
    let half = Texture::new(2, 1, vec![0x0000_ff00, 0xff00_ff00]).unwrap();
    let mk = |z: f32, color: Vec4, material: Material| {
        let mut b = MeshBuilder::new();
        let m = b.material(material);
        let c = [(8.0, 8.0, 0.0, 0.0), (56.0, 8.0, 1.0, 0.0), (56.0, 56.0, 1.0, 1.0), (8.0, 56.0, 0.0, 1.0)];
        let idx: Vec<u32> = c
            .iter()
            .map(|&(x, y, u, v)| b.vertex(Vertex { position: Vec3::new(x, y, z), uv: Vec2::new(u, v), color }))
            .collect();
        b.polygon(&idx, m);
        b.build().unwrap()
    };
    let front = mk(
        1.0,
        Vec4::ONE,
        Material {
            texture: Some(0),
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            double_sided: true,
            ..Material::default()
        },
    );
    let back = mk(0.0, RED, Material { double_sided: true, ..Material::default() });
    for method in Method::ALL {
        let (img, _) =
            render(&[back.clone(), front.clone()], std::slice::from_ref(&half), &camera, w, h, &opts(method));
        // Left half shows red through the hole, right half green.
        assert_eq!(img[32 * w + 16], 0xff0000, "{method}");
        assert_eq!(img[32 * w + 48], 0x00ff00, "{method}");
    }
}

#[test]
fn wrap_modes_and_filters_through_the_pipeline() {
    let (w, h) = (64usize, 64usize);
    let camera = pixel_camera(w, h);
    let tex = Texture::new(2, 1, vec![0xffff_0000, 0xff00_00ff]).unwrap();
    // uv from -1 to 2 across the quad: three texture widths.
    for (wrap, expect) in [
        (Wrap::Repeat, [0xff0000, 0x0000ff, 0xff0000, 0x0000ff, 0xff0000, 0x0000ff]),
        (Wrap::ClampToEdge, [0xff0000, 0xff0000, 0xff0000, 0x0000ff, 0x0000ff, 0x0000ff]),
        (Wrap::MirroredRepeat, [0x0000ff, 0xff0000, 0xff0000, 0x0000ff, 0x0000ff, 0xff0000]),
    ] {
        let mut b = MeshBuilder::new();
        let m = b.material(Material {
            texture: Some(0),
            sampler: scanline_racer::render::Sampler { wrap_s: wrap, wrap_t: wrap },
            double_sided: true,
            ..Material::default()
        });
        let c = [(0.0, 0.0, -1.0), (48.0, 0.0, 2.0), (48.0, 64.0, 2.0), (0.0, 64.0, -1.0)];
        let idx: Vec<u32> = c
            .iter()
            .map(|&(x, y, u)| {
                b.vertex(Vertex { position: Vec3::new(x, y, 0.0), uv: Vec2::new(u, 0.5), color: Vec4::ONE })
            })
            .collect();
        b.polygon(&idx, m);
        let mesh = b.build().unwrap();
        let (img, _) =
            render(std::slice::from_ref(&mesh), std::slice::from_ref(&tex), &camera, w, h, &opts(Method::ZBuffer));
        let got: Vec<u32> = (0..6).map(|i| img[32 * w + i * 8 + 4]).collect();
        assert_eq!(got, expect, "{wrap:?}");
        let (bil, _) = render(
            std::slice::from_ref(&mesh),
            std::slice::from_ref(&tex),
            &camera,
            w,
            h,
            &RenderOptions { filter: Filter::Bilinear, ..opts(Method::ZBuffer) },
        );
        // Bilinear blends across the texel boundary at u = 0.5 (x = 24): a purple mix appears just before it.
        let mid = bil[32 * w + 23];
        assert!((mid >> 16) & 0xff > 40 && mid & 0xff > 40, "{wrap:?}: {mid:06x}");
    }
}

/// A see-through (screen-door) square over an opaque one: exactly the even pixels (x + y even) of the
/// overlap show the front colour, in every method, whichever is submitted first; the odd ones show the back.
#[test]
fn see_through_instances_draw_a_checkerboard_in_every_method() {
    let (w, h) = (64usize, 64usize);
    let cam = pixel_camera(w, h);
    let square = |x0: i64, y0: i64, x1: i64, y1: i64, z: f32, c: Vec4| {
        let (a, b, cc, d) = (pix(x0, y0, h, z), pix(x1, y0, h, z), pix(x1, y1, h, z), pix(x0, y1, h, z));
        tri_mesh(&[[a, b, cc], [a, cc, d]], &[c], true)
    };
    let back = square(8 * 16, 8 * 16, 40 * 16, 40 * 16, 10.0, Vec4::new(0.0, 0.0, 1.0, 1.0));
    let ghost = square(24 * 16, 24 * 16, 56 * 16, 56 * 16, 20.0, Vec4::new(1.0, 0.0, 0.0, 1.0));
    let meshes = [back, ghost];
    for ghost_first in [false, true] {
        let mut instances = vec![Instance::new(0, Mat4::IDENTITY), Instance::new(1, Mat4::IDENTITY).see_through()];
        if ghost_first {
            instances.reverse();
        }
        for m in Method::ALL {
            let mut frame = vec![0u32; w * h];
            let list =
                DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
            let o = RenderOptions { background: Some(0), ..opts(m) };
            Renderer::new().render(&mut frame, w, h, &cam, &list, &o).unwrap();
            for y in 0..h {
                for x in 0..w {
                    let in_back = (8..40).contains(&x) && (8..40).contains(&y);
                    let in_ghost = (24..56).contains(&x) && (24..56).contains(&y);
                    let want = match (in_ghost && (x + y) % 2 == 0, in_back) {
                        (true, _) => 0xff0000,
                        (false, true) => 0x0000ff,
                        (false, false) => 0,
                    };
                    assert_eq!(frame[y * w + x], want, "{m} ghost first {ghost_first} at ({x}, {y})");
                }
            }
        }
    }
}

/// An orthographic camera whose x and y units are the pixels of a `w` x `h` frame, looking down -z from
/// z = 100.
fn pixel_camera(w: usize, h: usize) -> Camera {
    Camera {
        view: Mat4::from_translation(Vec3::new(-(w as f32) * 0.5, -(h as f32) * 0.5, -100.0)),
        projection: scanline_racer::render::Projection::Orthographic {
            xmag: w as f32 * 0.5,
            ymag: h as f32 * 0.5,
            znear: 1.0,
            zfar: 300.0,
        },
    }
}

/// Small triangles that follow one another with different paints (flat colours, two textures, white and
/// tinted, with and without a cutoff) are drawn by loops shared between neighbours that paint alike: every
/// triangle must still get its own paint. The reference draws each triangle alone, where nothing is shared.
#[test]
fn neighbouring_small_triangles_of_different_paints_each_keep_their_own() {
    let (w, h) = (96usize, 40usize);
    let camera = pixel_camera(w, h);
    let stripes = |seed: u32| {
        let texels = (0..16u32).map(|i| 0xff00_0000 | (i * 0x0011_0d07).wrapping_mul(seed) & 0x00ff_ffff).collect();
        Texture::new(4, 4, texels).unwrap()
    };
    let textures = [stripes(3), stripes(7)];
    let tinted = Vec4::new(0.5, 0.75, 0.25, 1.0);
    let materials = [
        Material { base_color: RED, ..Material::default() },
        Material { base_color: BLUE, ..Material::default() },
        Material { texture: Some(0), ..Material::default() },
        Material { texture: Some(0), base_color: tinted, ..Material::default() },
        Material { texture: Some(1), ..Material::default() },
        Material { texture: Some(0), alpha_mode: AlphaMode::Mask { cutoff: 0.5 }, ..Material::default() },
        Material { texture: Some(1), base_color: tinted, ..Material::default() },
    ];
    // Runs of equal paints and every change between neighbours.
    let pattern = [0, 0, 1, 2, 2, 3, 2, 4, 4, 5, 2, 6, 3, 3, 0, 6, 6, 1, 5, 5, 4, 0, 2, 1];
    let mesh_of = |tris: &[(usize, usize)]| {
        let mut b = MeshBuilder::new();
        let ms: Vec<u32> = materials.iter().map(|m| b.material(Material { double_sided: true, ..m.clone() })).collect();
        for &(i, m) in tris {
            let (x, y) = ((i % 12) as f32 * 8.0 + 0.5, (i / 12) as f32 * 10.0 + 0.5);
            let corners = [(x, y, 0.0, 0.0), (x + 6.0, y, 1.0, 0.0), (x, y + 6.0, 0.0, 1.0)];
            let idx: Vec<u32> = corners
                .iter()
                .map(|&(x, y, u, v)| {
                    let color = Vec4::ONE;
                    b.vertex(Vertex { position: Vec3::new(x, y, (i % 5) as f32), uv: Vec2::new(u, v), color })
                })
                .collect();
            b.polygon(&idx, ms[m]);
        }
        b.build().unwrap()
    };
    let all: Vec<(usize, usize)> = (0..36).map(|i| (i, pattern[i % pattern.len()])).collect();
    for method in [Method::ZBuffer, Method::BucketFar, Method::BucketNear] {
        let o = opts(method);
        let (frame, _) = render(&[mesh_of(&all)], &textures, &camera, w, h, &o);
        let mut expected = vec![0u32; w * h];
        for t in &all {
            let (alone, _) = render(&[mesh_of(&[*t])], &textures, &camera, w, h, &o);
            for (e, a) in expected.iter_mut().zip(&alone) {
                *e |= a;
            }
        }
        assert_eq!(frame, expected, "{method}");
        // Each triangle is drawn (about 18 pixels), and the paints differ.
        assert!(frame.iter().filter(|&&p| p != 0).count() > 36 * 12, "{method}");
        let distinct: std::collections::BTreeSet<u32> = frame.iter().copied().collect();
        assert!(distinct.len() > 12, "{method}: {} colours", distinct.len());
    }
}

/// Flat small triangles lying on one another at one depth, narrow ones (a box of at most four columns,
/// drawn four columns at a time) and wider ones (drawn a run at a time) in turn, all in one group: ties
/// must keep the order each method promises, exactly as if each triangle were drawn alone onto the frame
/// in turn. The z-buffer keeps the first (strictly nearer wins), the painter's bucket-far the last, and so
/// does bucket-near: it draws each pixel once, in exactly the reverse of bucket-far's order, so its first
/// drawn is the last submitted.
#[test]
fn overlapping_narrow_and_wide_small_triangles_keep_their_drawing_order() {
    let (w, h) = (40usize, 24usize);
    let camera = pixel_camera(w, h);
    let mut seed = 9u32;
    let mut unit = move || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / 16_777_216.0
    };
    let tris: Vec<([Vec3; 3], Vec4)> = (0..60)
        .map(|i| {
            let size = if i % 3 == 0 { 6.5 } else { 2.0 + unit() };
            let (x, y) = (4.0 + unit() * 28.0, 3.0 + unit() * 14.0);
            let c = Vec4::new((i % 5) as f32 / 4.0, (i % 4) as f32 / 3.0, (1 + i / 20) as f32 / 3.0, 1.0);
            ([Vec3::new(x, y, 0.0), Vec3::new(x + size, y + unit(), 0.0), Vec3::new(x + unit(), y + size, 0.0)], c)
        })
        .collect();
    let mesh_of = |tris: &[([Vec3; 3], Vec4)]| {
        let mut b = MeshBuilder::new();
        let m = b.material(Material { double_sided: true, ..Material::default() });
        for (corners, color) in tris {
            let idx: Vec<u32> =
                corners.iter().map(|&position| b.vertex(Vertex { position, uv: Vec2::ZERO, color: *color })).collect();
            b.polygon(&idx, m);
        }
        b.build().unwrap()
    };
    for (method, first_wins) in [(Method::ZBuffer, true), (Method::BucketFar, false), (Method::BucketNear, false)] {
        let o = opts(method);
        let (frame, _) = render(&[mesh_of(&tris)], &[], &camera, w, h, &o);
        let mut expected = vec![0u32; w * h];
        let mut layers = vec![0u32; w * h];
        for t in &tris {
            let (alone, _) = render(&[mesh_of(std::slice::from_ref(t))], &[], &camera, w, h, &o);
            for ((e, n), &a) in expected.iter_mut().zip(&mut layers).zip(&alone) {
                if a != 0 {
                    *n += 1;
                    if !first_wins || *n == 1 {
                        *e = a;
                    }
                }
            }
        }
        assert_eq!(frame, expected, "{method}");
        // The triangles do lie on one another.
        let stacked = layers.iter().filter(|&&n| n >= 2).count();
        assert!(stacked > 100, "{method}: only {stacked} pixels covered twice or more");
    }
}

/// A grid of `cells` x `cells` squares (two triangles each) over `x0..x1` x `y0..y1` at depth 0, one colour.
fn grid(cells: usize, (x0, x1): (f32, f32), (y0, y1): (f32, f32), color: Vec4) -> scanline_racer::render::Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { double_sided: true, ..Material::default() });
    let at = |i: usize, j: usize| {
        let (u, v) = (i as f32 / cells as f32, j as f32 / cells as f32);
        Vec3::new(x0 + (x1 - x0) * u, y0 + (y1 - y0) * v, 0.0)
    };
    for j in 0..cells {
        for i in 0..cells {
            let idx: Vec<u32> = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
                .into_iter()
                .map(|position| b.vertex(Vertex { position, uv: Vec2::ZERO, color }))
                .collect();
            b.polygon(&[idx[0], idx[1], idx[2]], m);
            b.polygon(&[idx[0], idx[2], idx[3]], m);
        }
    }
    b.build().unwrap()
}

/// Small objects (set up on one thread) and big ones (set up in pieces on the pool, whose polygons the
/// z-buffer draws from where their pieces left them) in turn, all lying on one another at one depth, with
/// a big one off screen (culled) between them and enough small ones together for the fill to bin them in
/// several pieces: every method must keep the submission order across them (the z-buffer's first drawn
/// wins a tie, the painter's last), for every thread count, exactly as if each object were drawn alone in
/// turn, and one renderer going from method to method and thread count to thread count must too.
#[test]
fn small_and_big_objects_in_turn_keep_the_submission_order_for_every_thread_count() {
    let (w, h) = (64usize, 48usize);
    let camera = pixel_camera(w, h);
    let c = |r: f32, g: f32, b: f32| Vec4::new(r, g, b, 1.0);
    let meshes = [
        grid(2, (4.0, 30.0), (4.0, 30.0), c(1.0, 0.0, 0.0)),
        grid(24, (10.0, 50.0), (8.0, 40.0), c(0.0, 1.0, 0.0)),
        grid(2, (20.0, 44.0), (16.0, 36.0), c(0.0, 0.0, 1.0)),
        grid(24, (1000.0, 1040.0), (8.0, 40.0), c(1.0, 0.0, 1.0)),
        grid(22, (2.0, 26.0), (30.0, 46.0), c(0.5, 0.0, 0.0)),
        grid(22, (14.0, 40.0), (26.0, 47.0), c(0.0, 0.5, 0.0)),
        grid(23, (30.0, 60.0), (2.0, 44.0), c(1.0, 1.0, 0.0)),
        grid(3, (0.0, 64.0), (20.0, 28.0), c(0.0, 1.0, 1.0)),
    ];
    let big = meshes.iter().filter(|m| m.polygons().len() >= 1024).count();
    assert_eq!(big, 3, "three objects big enough to be set up in pieces");
    let small_polygons: usize = meshes.iter().map(|m| m.polygons().len()).filter(|&n| n < 1024).sum();
    assert!(small_polygons >= 1024, "the small objects together are binned in several pieces");
    let methods = [(Method::ZBuffer, true), (Method::BucketFar, false), (Method::BucketNear, false)];
    let mut expected = Vec::new();
    for (method, first_wins) in methods {
        let mut e = vec![0u32; w * h];
        let mut layers = vec![0u32; w * h];
        for m in &meshes {
            let (alone, _) = render(std::slice::from_ref(m), &[], &camera, w, h, &opts(method));
            for ((e, n), &a) in e.iter_mut().zip(&mut layers).zip(&alone) {
                if a != 0 {
                    *n += 1;
                    if !first_wins || *n == 1 {
                        *e = a;
                    }
                }
            }
        }
        // Every object on screen is partly on top of another and partly under one.
        assert!(layers.iter().filter(|&&n| n >= 3).count() > 100, "{method}: too few stacked pixels");
        expected.push(e);
    }
    let instances: Vec<Instance> = (0..meshes.len()).map(|m| Instance::new(m, Mat4::IDENTITY)).collect();
    let list = DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
    let mut reused = Renderer::new();
    let mut filled: Option<u64> = None;
    for threads in [1usize, 2, 3, 5] {
        for (k, (method, _)) in methods.into_iter().enumerate() {
            let o = RenderOptions { threads, ..opts(method) };
            for r in [&mut Renderer::new(), &mut reused] {
                let mut frame = vec![0u32; w * h];
                let stats = r.render(&mut frame, w, h, &camera, &list, &o).unwrap();
                assert!(frame == expected[k], "{method}: {threads} threads do not keep the submission order");
                assert_eq!(stats.objects_culled, 1, "{method}: {threads} threads");
                let filled = *filled.get_or_insert(stats.pieces_filled);
                assert_eq!(stats.pieces_filled, filled, "{method}: {threads} threads");
                assert!(filled >= 2 * 1024 + 1024, "{method}: {filled} pieces filled");
            }
        }
    }
}

/// A scene of many small objects, as a dressed course is: more instances than the visibility pass handles
/// on one thread (it chooses and culls them in chunks on the pool), some off screen (culled), a third of them
/// LOD sets at sizes that pick each of their three models, and enough polygons together for runs of them to
/// be set up in pieces of whole objects. Every method must draw the same frames, count the same and choose
/// the same models for every thread count, over frames that carry the LOD history from one to the next.
#[test]
fn many_small_objects_are_drawn_alike_by_every_thread_count() {
    use scanline_racer::render::LodSet;
    let (w, h) = (96usize, 64usize);
    let camera = pixel_camera(w, h);
    let c = |i: usize| Vec4::new((i % 5) as f32 / 4.0, (i % 3) as f32 / 2.0, (i % 7) as f32 / 6.0, 1.0);
    // Meshes 0-2: a LOD set's close, middle and long models; 3-5: plain objects.
    let meshes: Vec<_> = (0..6).map(|k| grid([3, 2, 1, 2, 3, 1][k], (-3.0, 3.0), (-3.0, 3.0), c(k))).collect();
    let lod_sets = [LodSet { meshes: [0, 1, 2], switch_px: [20.0, 8.0] }];
    let mut seed = 7u32;
    let mut next = |n: u32| {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) % n
    };
    let instances: Vec<Instance> = (0..1500)
        .map(|i| {
            // One in ten lies far off screen, to be culled.
            let x = if i % 10 == 9 { 5000.0 } else { next(w as u32 + 8) as f32 - 4.0 };
            let (y, z) = (next(h as u32 + 8) as f32 - 4.0, next(80) as f32 - 40.0);
            let scale = [0.4f32, 1.0, 2.5, 5.0][next(4) as usize];
            let model = Mat4::from_translation(Vec3::new(x, y, z)) * Mat4::from_scale(Vec3::splat(scale));
            if i % 3 == 0 { Instance::of_lod_set(0, model) } else { Instance::new(3 + i % 3, model) }
        })
        .collect();
    let list =
        DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &lod_sets, view_lists: None };
    let polygons: usize =
        instances.iter().map(|i| meshes[if i.lod.is_some() { 1 } else { i.mesh }].polygons().len()).sum();
    assert!(polygons >= 4 * 1024, "enough polygons for runs set up in pieces ({polygons})");
    for method in Method::ALL {
        let mut first: Option<Vec<(Vec<u32>, [u64; 6])>> = None;
        for threads in [1usize, 2, 3, 5] {
            let mut r = Renderer::new();
            let frames: Vec<(Vec<u32>, [u64; 6])> = (0..3)
                .map(|_| {
                    let mut frame = vec![0u32; w * h];
                    let s =
                        r.render(&mut frame, w, h, &camera, &list, &RenderOptions { threads, ..opts(method) }).unwrap();
                    // The z-buffer's pixel counts leave out what its coarse depth skipped, which depends on
                    // the bands (`Stats::pixels_shaded`); its frames must still be the same.
                    let written = if method == Method::ZBuffer { 0 } else { s.pixels_written };
                    let counts = [s.objects_culled, s.polygons_drawn, s.lod_close, s.lod_mid, s.lod_long, written];
                    (frame, counts)
                })
                .collect();
            let counts = frames[0].1;
            // The 150 far off screen, and a few at the frame's edges.
            assert!((150..300).contains(&counts[0]), "{method}: {} instances culled", counts[0]);
            assert!(counts[2] > 0 && counts[3] > 0 && counts[4] > 0, "{method}: every LOD level is used: {counts:?}");
            match &first {
                None => first = Some(frames),
                Some(f) => {
                    for (k, (a, b)) in f.iter().zip(&frames).enumerate() {
                        assert_eq!(a.1, b.1, "{method}: frame {k}, {threads} threads count differently from 1");
                        assert!(a.0 == b.0, "{method}: frame {k}, {threads} threads differ from 1");
                    }
                }
            }
        }
    }
}
