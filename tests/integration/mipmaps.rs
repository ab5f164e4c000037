//! Mip-maps: the level each choice (per polygon, per span, per pixel) takes at known scales, trilinear
//! filtering at whole levels, frames identical for every thread count, far detail filtered away, and the
//! anisotropic filter nearer the pixel's integral than the others.

use crate::common::*;
use glam::{Vec2, Vec3, Vec4};
use scanline_racer::render::{
    Camera, DrawList, Filter, Instance, Material, Mesh, MeshBuilder, MipMode, RenderOptions, Texture, TextureMode,
    Vertex,
};

fn noise_texture(w: u32, h: u32, mut seed: u32) -> Texture {
    let texels = (0..w * h)
        .map(|_| {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            seed | 0xff00_0000
        })
        .collect();
    Texture::new(w, h, texels).unwrap()
}

/// A square of `side` pixels at `(16, 16)` of a 64x64 frame, mapping the whole texture once, as one quad
/// or (with `triangles`) as two triangles (which small enough take the small-triangle path).
fn square(side: i64, triangles: bool) -> Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { texture: Some(0), double_sided: true, ..Material::default() });
    let corner = |b: &mut MeshBuilder, x: i64, y: i64| {
        let uv = Vec2::new(x as f32, y as f32);
        b.vertex(Vertex { position: pix((16 + x * side) * 16, (16 + y * side) * 16, 64, 0.0), uv, color: Vec4::ONE })
    };
    let c = [corner(&mut b, 0, 0), corner(&mut b, 1, 0), corner(&mut b, 1, 1), corner(&mut b, 0, 1)];
    if triangles {
        b.polygon(&[c[0], c[1], c[2]], m);
        b.polygon(&[c[0], c[2], c[3]], m);
    } else {
        b.polygon(&c, m);
    }
    b.build().unwrap()
}

fn draw(mesh: &Mesh, texture: &Texture, filter: Filter, mip: MipMode, threads: usize) -> Vec<u32> {
    let o = RenderOptions { filter, mip, threads, background: Some(0), ..RenderOptions::default() };
    render(std::slice::from_ref(mesh), std::slice::from_ref(texture), &pixel_camera(64, 64), 64, 64, &o).0
}

#[test]
fn each_choice_takes_the_level_of_its_scale_and_level_zero_when_magnified() {
    for (side, triangles) in [(32, false), (16, true)] {
        let mesh = square(side, triangles);
        for k in 0..4u32 {
            // One pixel spans 2^k texels: level k, whose texels drawn alone (one texel a pixel) take level 0.
            let size = (side as u32) << k;
            let chain = noise_texture(size, size, k + 1);
            let alone = Texture::new(side as u32, side as u32, chain.level(k as usize).texels().to_vec()).unwrap();
            for mip in [MipMode::Polygon, MipMode::Span, MipMode::Pixel] {
                let what = format!("{side}-pixel square, 2^{k} texels a pixel, {mip}");
                for filter in [Filter::Nearest, Filter::Bilinear] {
                    let got = draw(&mesh, &chain, filter, mip, 1);
                    assert!(got == draw(&mesh, &alone, filter, MipMode::Off, 1), "{what} {filter:?}");
                }
                // At a whole level trilinear is bilinear in that level.
                let got = draw(&mesh, &chain, Filter::Trilinear, mip, 1);
                assert!(got == draw(&mesh, &alone, Filter::Bilinear, MipMode::Off, 1), "{what} trilinear");
            }
            if k > 0 {
                let off = draw(&mesh, &chain, Filter::Nearest, MipMode::Off, 1);
                assert!(off != draw(&mesh, &chain, Filter::Nearest, MipMode::Pixel, 1), "the levels differ");
            }
        }
        // Magnified (a quarter of a texel a pixel): level 0 whatever the choice.
        let small = noise_texture(side as u32 / 4, side as u32 / 4, 9);
        for filter in Filter::ALL {
            let off = draw(&mesh, &small, filter, MipMode::Off, 1);
            for mip in MipMode::ALL {
                assert!(draw(&mesh, &small, filter, mip, 1) == off, "magnified {mip} {filter:?}");
            }
        }
    }
    // With mip-maps off, trilinear is bilinear.
    let (mesh, t) = (square(32, false), noise_texture(128, 128, 4));
    assert!(draw(&mesh, &t, Filter::Trilinear, MipMode::Off, 1) == draw(&mesh, &t, Filter::Bilinear, MipMode::Off, 1));
}

/// A checkerboard (8x8 texel checks on a 64x64 texture, a tile every 4 m) on the ground from the camera to
#[test]
fn min_bilinear_is_nearest_on_a_magnified_polygon_and_bilinear_on_a_minified_one() {
    // As a quad and as two triangles small enough for the small-triangle path (which a minified triangle
    // leaves for the bilinear fill).
    for (side, triangles) in [(32, false), (16, true)] {
        let mesh = square(side, triangles);
        // A quarter of a texel a pixel, then one and a half and three (not a whole level, where bilinear
        // samples fall on texel centres and equal the nearest ones).
        let side_texels = side as u32;
        for (size, minified) in [(side_texels / 4, false), (side_texels * 3 / 2, true), (side_texels * 3, true)] {
            let t = noise_texture(size, size, size);
            let what = format!("{side}-pixel square of {size}x{size} texels");
            let (filter, other) =
                if minified { (Filter::Bilinear, Filter::Nearest) } else { (Filter::Nearest, Filter::Bilinear) };
            let want = draw(&mesh, &t, filter, MipMode::Polygon, 1);
            assert!(want != draw(&mesh, &t, other, MipMode::Polygon, 1), "{what}: the filters differ");
            for threads in [1, 2, 3] {
                assert!(
                    draw(&mesh, &t, Filter::MinBilinear, MipMode::Polygon, threads) == want,
                    "{what}, {threads} threads"
                );
            }
            // Its level is the polygon's whatever the mip choice says.
            for mip in [MipMode::Off, MipMode::Span, MipMode::Pixel] {
                assert!(draw(&mesh, &t, Filter::MinBilinear, mip, 1) == want, "{what}, {mip}");
            }
        }
    }
}

#[test]
fn area_is_the_pixel_s_integral_over_magnified_texels_and_bilinear_over_minified_ones() {
    // A 4x4 checkerboard on a square of 30 pixels (7.5 pixels a texel: texel edges inside pixels), or 15
    // as two triangles (small enough for the small-triangle path, which `area` leaves to the polygon fill).
    let checker =
        Texture::new(4, 4, (0..16).map(|i| if (i % 4 + i / 4) % 2 == 1 { 0xffff_ffff } else { 0xff00_0000 }).collect())
            .unwrap();
    for (side, triangles, within) in [(30i64, false, 1.0), (15, true, 4.0)] {
        let mesh = square(side, triangles);
        let got = draw(&mesh, &checker, Filter::Area, MipMode::Polygon, 1);
        let nearest = draw(&mesh, &checker, Filter::Nearest, MipMode::Polygon, 1);
        // The white share of pixel `(x, y)`'s square: the checker is white where exactly one of the column
        // and the row of texels is odd, so the share is `a (1 - b) + (1 - a) b` with `a` the share of the
        // pixel's span across in odd columns and `b` that down in odd rows.
        let odd_share = |p: i64| {
            let (lo, hi) = ((p - 16) as f64 * 4.0 / side as f64, (p - 15) as f64 * 4.0 / side as f64);
            (0..4)
                .filter(|c| c % 2 == 1)
                .map(|c| (hi.min(f64::from(c + 1)) - lo.max(f64::from(c))).max(0.0))
                .sum::<f64>()
                / (hi - lo)
        };
        let (mut worst, mut worst_nearest, mut between) = (0.0f64, 0.0f64, 0);
        for y in 16..16 + side {
            for x in 16..16 + side {
                let (a, b) = (odd_share(x), odd_share(y));
                let want = (a * (1.0 - b) + (1.0 - a) * b) * 255.0;
                let level = |frame: &[u32]| f64::from(frame[(y * 64 + x) as usize] & 0xff);
                worst = worst.max((level(&got) - want).abs());
                worst_nearest = worst_nearest.max((level(&nearest) - want).abs());
                between += usize::from(!matches!(got[(y * 64 + x) as usize] & 0xff, 0 | 255));
            }
        }
        // The sample's position is kept to 1/256 of a texel, an error the footprint (2/15 or 4/15 of a texel)
        // scales up to 7.5 or 3.75 levels; measured: half a level on the quad, 3.5 on the triangles.
        assert!(worst <= within, "{side}-pixel square: {worst} levels from the integral");
        assert!(
            worst_nearest >= 100.0 && between >= side as usize * 2,
            "nearest steps ({worst_nearest}), area blends ({between} pixels)"
        );
        for threads in [2, 3] {
            assert!(draw(&mesh, &checker, Filter::Area, MipMode::Polygon, threads) == got, "{side}: {threads} threads");
        }
        // A coarser mip bias widens the box (more pixels blended, level 0 kept); a finer one changes nothing.
        let biased = |mip_bias: f32| {
            let o = RenderOptions {
                filter: Filter::Area,
                mip_bias,
                threads: 1,
                background: Some(0),
                ..RenderOptions::default()
            };
            render(std::slice::from_ref(&mesh), std::slice::from_ref(&checker), &pixel_camera(64, 64), 64, 64, &o).0
        };
        let blended = |frame: &[u32]| frame.iter().filter(|&&c| !matches!(c & 0xff, 0 | 255)).count();
        assert!(biased(-1.0) == got, "{side}: a finer bias");
        assert!(blended(&biased(1.0)) > between, "{side}: a coarser bias blends more");
        // Minified (one and a half, three texels a pixel): bilinear in the polygon's level, as `min-bilinear`.
        for size in [side as u32 * 3 / 2, side as u32 * 3] {
            let t = noise_texture(size, size, size);
            let want = draw(&mesh, &t, Filter::Bilinear, MipMode::Polygon, 1);
            for mip in MipMode::ALL {
                assert!(draw(&mesh, &t, Filter::Area, mip, 1) == want, "{side}-pixel square of {size} texels, {mip}");
            }
        }
    }
}

#[test]
fn a_mip_bias_moves_every_choice_by_its_levels() {
    let mesh = square(16, false);
    for k in 1..3u32 {
        // One pixel spans 2^k texels (level k); a bias of b takes level k + b: the same pixels as that
        // level's texels drawn without mip-maps.
        let size = 16u32 << k;
        let chain = noise_texture(size, size, 7 + k);
        for bias in [-1.0f32, 1.0] {
            let j = (k as f32 + bias) as usize;
            let level = chain.level(j);
            let alone = Texture::new(level.width(), level.height(), level.texels().to_vec()).unwrap();
            let want = draw(&mesh, &alone, Filter::Nearest, MipMode::Off, 1);
            for mip in [MipMode::Polygon, MipMode::Span, MipMode::Pixel] {
                let o =
                    RenderOptions { mip, mip_bias: bias, threads: 1, background: Some(0), ..RenderOptions::default() };
                let got = render(
                    std::slice::from_ref(&mesh),
                    std::slice::from_ref(&chain),
                    &pixel_camera(64, 64),
                    64,
                    64,
                    &o,
                )
                .0;
                assert!(got == want, "2^{k} texels a pixel, bias {bias}, {mip}: not level {j}");
            }
        }
        // No bias, or one that is not a number, keeps level k.
        let plain = draw(&mesh, &chain, Filter::Nearest, MipMode::Polygon, 1);
        let o = RenderOptions { mip_bias: f32::NAN, threads: 1, background: Some(0), ..RenderOptions::default() };
        let nan =
            render(std::slice::from_ref(&mesh), std::slice::from_ref(&chain), &pixel_camera(64, 64), 64, 64, &o).0;
        assert!(nan == plain, "a NaN bias");
    }
}

/// 400 m away, in strips 10 m deep (so each strip has a level of its own per polygon).
fn checker_plane() -> (Mesh, Texture, Camera) {
    let texels = (0..64 * 64).map(|i| if ((i % 64) / 8 + (i / 64) / 8) % 2 == 0 { 0xffff_ffff } else { 0xff00_0000 });
    let texture = Texture::new(64, 64, texels.collect()).unwrap();
    let mut b = MeshBuilder::new();
    let m = b.material(Material { texture: Some(0), double_sided: true, ..Material::default() });
    let mut v = |x: f32, z: f32| {
        b.vertex(Vertex { position: Vec3::new(x, 0.0, z), uv: Vec2::new(x / 4.0, z / 4.0), color: Vec4::ONE })
    };
    let mut quads = vec![];
    for i in 0..40 {
        let (z0, z1) = (4.0 - 10.0 * i as f32, -6.0 - 10.0 * i as f32);
        quads.push([v(-200.0, z0), v(200.0, z0), v(200.0, z1), v(-200.0, z1)]);
    }
    for q in quads {
        b.polygon(&q, m);
    }
    let camera = Camera::look_at(Vec3::new(0.3, 1.5, 0.0), Vec3::new(0.3, 1.5, -100.0), 1.0, 0.1, Some(1000.0));
    (b.build().unwrap(), texture, camera)
}

const PLANE: (usize, usize) = (320, 240);

fn draw_plane(filter: Filter, mip: MipMode, threads: usize, mode: TextureMode) -> Vec<u32> {
    let (mesh, texture, camera) = checker_plane();
    let o = RenderOptions { filter, mip, threads, texture_mode: mode, background: Some(0), ..Default::default() };
    let (w, h) = PLANE;
    render(std::slice::from_ref(&mesh), std::slice::from_ref(&texture), &camera, w, h, &o).0
}

#[test]
fn frames_with_mip_maps_are_bit_identical_for_every_thread_count() {
    for mip in MipMode::ALL {
        for filter in Filter::ALL {
            for mode in [TextureMode::Perspective, TextureMode::Subdivided] {
                let one = draw_plane(filter, mip, 1, mode);
                for threads in [2, 3] {
                    assert!(
                        draw_plane(filter, mip, threads, mode) == one,
                        "{mip} {filter:?} {mode:?}: {threads} threads"
                    );
                }
            }
        }
    }
}

#[test]
fn a_textured_model_with_small_triangles_is_drawn_alike_by_every_thread_count_under_every_mip_choice() {
    let scene = scanline_racer::asset::load(&samples().join("Duck/Duck.gltf")).unwrap();
    let (w, h) = (203usize, 157usize);
    // Far enough for the duck's triangles to be small and its texture minified.
    let camera = scene.framing_camera(w as f32 / h as f32);
    let mut nearest = vec![];
    for mip in MipMode::ALL {
        for filter in [Filter::Nearest, Filter::Trilinear] {
            let mut first: Option<Vec<u32>> = None;
            for threads in [1usize, 2, 3] {
                let o = RenderOptions { filter, mip, threads, ..RenderOptions::default() };
                let mut frame = vec![0u32; w * h];
                scanline_racer::render::Renderer::new()
                    .render(&mut frame, w, h, &camera, &scene.draw_list(), &o)
                    .unwrap();
                match &first {
                    None => first = Some(frame),
                    Some(f) => assert!(*f == frame, "{mip} {filter:?}: {threads} threads differ from 1"),
                }
            }
            if filter == Filter::Nearest {
                nearest.extend(first);
            }
        }
    }
    // The duck's texture is minified: every choice takes other levels than off does.
    for (k, frame) in nearest.iter().enumerate().skip(1) {
        assert!(*frame != nearest[0], "{} draws as off", MipMode::ALL[k]);
    }
}

/// The mean absolute difference of each pixel's grey level from its right and lower neighbours over rows
/// `rows`: the frame's high-frequency energy there.
fn energy(frame: &[u32], rows: std::ops::Range<usize>) -> f64 {
    let (w, _) = PLANE;
    let grey = |p: u32| f64::from((p >> 16 & 0xff) + (p >> 8 & 0xff) + (p & 0xff)) / 3.0;
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in rows {
        for x in 0..w - 1 {
            let p = grey(frame[y * w + x]);
            sum += (p - grey(frame[y * w + x + 1])).abs() + (p - grey(frame[(y + 1) * w + x])).abs();
            n += 1.0;
        }
    }
    sum / n
}

#[test]
fn mip_maps_take_the_high_frequencies_out_of_the_distance_and_keep_the_foreground() {
    let (_, h) = PLANE;
    // The horizon is the middle row: the 24 rows below it are 13 m to 400 m away, the bottom rows 2 m. (The
    // checks are 8 texels, so levels 1 to 3 hold the same checks, smaller: nearest sampling changes only from
    // level 4 on, where the checks average to grey.)
    let (far, near) = (h / 2 + 1..h / 2 + 25, h - 30..h - 1);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("mipmaps");
    std::fs::create_dir_all(&dir).unwrap();
    let (w, _) = PLANE;
    let off = draw_plane(Filter::Nearest, MipMode::Off, 1, TextureMode::Perspective);
    write_png(&dir.join("plane-off-nearest.png"), &off, w, h);
    let (far_off, near_off) = (energy(&off, far.clone()), energy(&off, near.clone()));
    eprintln!("mip off, nearest: far {far_off:.1}, near {near_off:.1}");
    assert!(far_off > 40.0, "without mip-maps the distance aliases: {far_off:.1}");
    for (mip, filter, most) in [
        (MipMode::Pixel, Filter::Trilinear, 0.1),
        (MipMode::Span, Filter::Trilinear, 0.1),
        (MipMode::Pixel, Filter::Nearest, 0.25),
        // A strip 10 m deep gets one level, by its mean footprint (smaller than the steepest one): only the
        // most distant strips turn grey.
        (MipMode::Polygon, Filter::Nearest, 0.8),
    ] {
        let frame = draw_plane(filter, mip, 1, TextureMode::Perspective);
        write_png(&dir.join(format!("plane-{mip}-{}.png", filter.name())), &frame, w, h);
        let (f, n) = (energy(&frame, far.clone()), energy(&frame, near.clone()));
        eprintln!("mip {mip}, {filter:?}: far {f:.1} ({:.2} of off), near {n:.1}", f / far_off);
        assert!(f < most * far_off, "{mip} {filter:?}: far energy {f:.1} against {far_off:.1} without");
        assert!(n > 0.5 * near_off, "{mip} {filter:?}: the foreground keeps its checks ({n:.1} against {near_off:.1})");
    }
}

#[test]
fn anisotropic_filtering_is_nearer_the_pixel_integral_than_nearest_or_trilinear() {
    // The receding plane with random texels (magnified in the foreground, minified towards the horizon),
    // against the integral over each pixel (16x16 nearest samples of level 0).
    let (mesh, _, camera) = checker_plane();
    let texture = noise_texture(64, 64, 7);
    let (w, h) = PLANE;
    let (meshes, textures) = (std::slice::from_ref(&mesh), std::slice::from_ref(&texture));
    let instances = [Instance::new(0, glam::Mat4::IDENTITY)];
    let list = DrawList { meshes, textures, instances: &instances, lod_sets: &[], view_lists: None };
    let reference = scanline_racer::measure::reference_frame_at(&camera, &list, (w, h), 0, 16).unwrap();
    let flip = |filter: Filter, mip: MipMode| {
        let o = RenderOptions { filter, mip, background: Some(0), ..RenderOptions::default() };
        let frame = render(meshes, textures, &camera, w, h, &o).0;
        scanline_racer::measure::flip(&reference, &frame, w, h).unwrap().mean
    };
    let nearest = flip(Filter::Nearest, MipMode::Polygon);
    let trilinear = flip(Filter::Trilinear, MipMode::Pixel);
    let aniso4 = flip(Filter::Anisotropic(4), MipMode::Pixel);
    let aniso16 = flip(Filter::Anisotropic(16), MipMode::Pixel);
    eprintln!("FLIP: nearest {nearest:.4}, trilinear {trilinear:.4}, aniso4 {aniso4:.4}, aniso16 {aniso16:.4}");
    assert!(aniso4 < 0.6 * nearest.min(trilinear), "aniso4 {aniso4} against {nearest} and {trilinear}");
    // More probes follow the long footprints towards the horizon more closely.
    assert!(aniso16 <= aniso4, "aniso16 {aniso16} against aniso4 {aniso4}");
    // The mip choice does not matter to it: it chooses its level at every pixel.
    assert_eq!(flip(Filter::Anisotropic(4), MipMode::Off), aniso4);
}

#[test]
fn render_and_replay_take_the_filter_and_the_mip_choice() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("mipmaps");
    std::fs::create_dir_all(&dir).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let run = |args: &[&str]| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
        c.args(args).current_dir(root).env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY");
        let o = run_bounded(&mut c, 60, &args.join(" "));
        assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
        o
    };
    let scene = "tests/scenes/courtyard.gltf";
    let mut frames = vec![];
    for (filter, mip) in [("nearest", "off"), ("trilinear", "pixel"), ("nearest", "polygon")] {
        let out = dir.join(format!("courtyard-{filter}-{mip}.png"));
        let o = run(&[
            "render",
            scene,
            "--filter",
            filter,
            "--mip",
            mip,
            "--stats",
            "json",
            "--out",
            out.to_str().unwrap(),
        ]);
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!((v["filter"].as_str(), v["mip"].as_str()), (Some(filter), Some(mip)));
        frames.push(read_png(&out).unwrap().0);
    }
    assert!(frames[0] != frames[1], "trilinear per pixel draws another frame");
    // A headless replay's frames: with mip-maps the distance differs.
    let mut replays = vec![];
    for mip in ["off", "pixel"] {
        let d = dir.join(format!("replay-{mip}"));
        let trace = "assets/replays/demo-race.trace";
        let d_str = d.to_str().unwrap();
        run(&[
            "replay",
            trace,
            "--headless",
            "--frames",
            d_str,
            "--every",
            "3000",
            "--filter",
            "trilinear",
            "--mip",
            mip,
        ]);
        replays.push(read_png(&d.join("frame_003000.png")).unwrap().0);
    }
    assert!(replays[0] != replays[1], "the replay's frames take --mip");
}
