//! Polygon set-up against its references: the clipper path and the scanline walker.

use glam::{Vec2, Vec3, Vec4};

use super::*;
use crate::render::core::test_rng::Lcg;
use crate::render::geometry::clip::ClipVolume;
use crate::render::{Camera, Filter, MeshBuilder, MipMode, TextureMode, Vertex};

/// Sets up every polygon of `mesh`, seen by an orthographic camera that maps `x, y` to pixels of a
/// 320x240 frame, with flat shading on the fast path.
fn set_up_in_pixels(mesh: &crate::render::Mesh) -> Batch {
    let camera = crate::render::Camera {
        view: glam::Mat4::from_translation(Vec3::new(-160.0, -120.0, -10.0)),
        projection: crate::render::Projection::Orthographic { xmag: 160.0, ymag: 120.0, znear: 1.0, zfar: 30.0 },
    };
    let transform = VertexTransform {
        clip_from_model: camera.clip_from_view(320, 240) * camera.view,
        depth_row: camera.view.row(2),
        volume: ClipVolume::new(320, 240, true),
        size: (320.0, 240.0),
        perspective: false,
    };
    let vertices: Vec<_> = mesh.vertices().iter().map(|v| transform.vertex(v.position)).collect();
    let setup = ObjectSetup {
        mesh,
        stored: None,
        vertices: &vertices,
        transform: &transform,
        key: DepthKey::Avg,
        ordered: true,
        perspective_attrs: false,
        object_key: None,
        textures: 0,
        door: crate::render::core::door::Door::NONE,
        mip_textures: &[],
        fast_path: FastPathRule { filter: Filter::Nearest, mode: TextureMode::Perspective, mip: MipMode::Off },
        antialiased: false,
        tall: false,
        width: 320,
    };
    let mut out = Batch::default();
    setup.run(0..mesh.polygons().len(), &mut out, &mut SetupScratch::default());
    out
}

#[test]
fn the_small_pieces_of_a_split_polygon_are_small_triangles_and_big_ones_keep_their_corners() {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { double_sided: true, ..Material::default() });
    // Two chevrons (a V with a notch in its top: not y-monotone), one 6 pixels across and one 60: each
    // is split into two triangles.
    for (x, s) in [(20.0, 1.0), (100.0, 10.0)] {
        let corners = [(0.0, 0.0), (3.0, 4.0), (6.0, 0.0), (3.0, 6.0)];
        let idx: Vec<u32> = corners
            .iter()
            .map(|&(cx, cy)| {
                let position = Vec3::new(x + cx * s, 20.0 + cy * s, 0.0);
                b.vertex(Vertex { position, uv: Vec2::ZERO, color: Vec4::ONE })
            })
            .collect();
        b.polygon(&idx, m);
    }
    let out = set_up_in_pixels(&b.build().unwrap());
    assert_eq!(out.counts.split, 2);
    let small: Vec<bool> = out.polys.iter().map(|p| p.small()).collect();
    assert_eq!(small, [true, true, false, false]);
    assert_eq!(out.small.len(), 2);
    // Only the big pieces' corners are kept.
    assert_eq!(out.screen.len(), 6);
}

/// Screen vertices as bits, every NaN one value (a NaN colour's sign and payload depend on operand order).
fn screen_bits(v: &[ScreenVertex]) -> Vec<(i32, i32, [u32; ATTRS])> {
    let b = |a: f32| if a.is_nan() { f32::NAN.to_bits() } else { a.to_bits() };
    v.iter().map(|v| (v.x.0, v.y.0, v.attrs.map(b))).collect()
}

// long: one scenario: a mesh set up both ways, compared polygon by polygon and then as a whole.
#[test]
fn polygons_set_up_from_projected_vertices_equal_the_clipper_path_bit_for_bit() {
    let mut rng = Lcg(3);
    let mut b = MeshBuilder::new();
    let tinted = b.material(Material { base_color: Vec4::new(0.9, 0.5, 0.25, 1.0), ..Material::default() });
    let biased = b.material(Material { double_sided: true, depth_bias: 2, ..Material::default() });
    let textured = b.material(Material { texture: Some(0), ..Material::default() });
    let masked = b.material(Material {
        texture: Some(0),
        double_sided: true,
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        base_color: Vec4::new(1.0, 1.0, 1.0, 0.75),
        ..Material::default()
    });
    // Corners whose colours differ only in green, which this material's colour zeroes: one colour.
    let no_green = b.material(Material { base_color: Vec4::new(1.0, 0.0, 1.0, 1.0), ..Material::default() });
    let materials = [biased, tinted, textured, masked, tinted, textured, masked];
    for i in 0..3000 {
        let corners = if i % 3 == 0 { 4 } else { 3 };
        let centre = Vec3::new(rng.unit() * 40.0 - 20.0, rng.unit() * 30.0 - 15.0, -1.0 - rng.unit() * 60.0);
        let idx: Vec<u32> = (0..corners)
            .map(|k| {
                let a = k as f32 / corners as f32 * std::f32::consts::TAU;
                let r = 0.2 + rng.unit() * 3.0;
                let position = centre + Vec3::new(libm::cosf(a) * r, libm::sinf(a) * r, rng.unit() - 0.5);
                // One colour per polygon for some, per corner for others.
                let c = match i % 2 {
                    // An infinite channel times the material's 0: a NaN colour, so not one colour.
                    _ if i % 22 == 0 => Vec4::new(0.5, f32::INFINITY, 0.5, 1.0),
                    _ if i % 11 == 0 => Vec4::new(0.5, rng.unit(), 0.5, 1.0),
                    0 => Vec4::splat(0.5),
                    _ => Vec4::new(rng.unit(), rng.unit(), 0.3, 1.0),
                };
                b.vertex(Vertex { position, uv: Vec2::new(rng.unit(), rng.unit()), color: c })
            })
            .collect();
        // Pairs of polygons share a material, so a run of polygons reuses its material facts.
        b.polygon(&idx, if i % 11 == 0 { no_green } else { materials[i / 2 % materials.len()] });
    }
    let mesh = b.build().unwrap();
    let (w, h) = (320.0, 240.0);
    let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, Some(100.0));
    let transform = VertexTransform {
        clip_from_model: camera.clip_from_view(320, 240) * camera.view,
        depth_row: camera.view.row(2),
        volume: ClipVolume::new(320, 240, true),
        size: (w, h),
        perspective: true,
    };
    let vertices: Vec<_> = mesh.vertices().iter().map(|v| transform.vertex(v.position)).collect();
    // With no textures in the draw list a textured material draws untextured.
    let cases = [
        (DepthKey::Avg, 1, None, true),
        (DepthKey::Min, 0, None, true),
        (DepthKey::Max, 1, None, true),
        (DepthKey::Avg, 1, Some(7.5), true),
        (DepthKey::Max, 1, None, false),
    ];
    for (key, textures, object_key, ordered) in cases {
        let setup = ObjectSetup {
            mesh: &mesh,
            stored: None,
            vertices: &vertices,
            transform: &transform,
            key,
            ordered,
            perspective_attrs: true,
            object_key,
            textures,
            door: crate::render::core::door::Door::NONE,
            mip_textures: &[],
            fast_path: FastPathRule { filter: Filter::Nearest, mode: TextureMode::Perspective, mip: MipMode::Off },
            antialiased: false,
            tall: false,
            width: 320,
        };
        let (mut fast, mut slow) = (Batch::default(), Batch::default());
        let (mut compared, mut small, mut textured) = (0, 0, 0);
        for (k, poly) in mesh.polygons().iter().enumerate() {
            let idx = mesh.polygon_indices(poly);
            if idx.iter().any(|&i| !vertices[i as usize].is_projected()) {
                continue; // crosses a plane: both go through the clipper
            }
            fast.clear();
            slow.clear();
            setup.run(k..k + 1, &mut fast, &mut SetupScratch::default());
            let material = &mesh.materials()[poly.material as usize];
            let Some(g) = setup.gather_clipped(idx, material, &mut slow, &mut SetupScratch::default()) else {
                // Wholly off one side of the frame: rejected by both.
                assert!(fast.polys.is_empty() && fast.counts.outside == 1, "polygon {k}");
                continue;
            };
            setup.finish(
                0,
                g,
                (material, &setup.material_setup(poly.material, material)),
                &mut slow,
                &mut SetupScratch::default(),
            );
            assert_eq!(screen_bits(&fast.screen), screen_bits(&slow.screen), "polygon {k}");
            assert_eq!(fast.small, slow.small, "polygon {k}");
            assert_eq!(fast.small_textured, slow.small_textured, "polygon {k}");
            assert_eq!(fast.polys, slow.polys, "polygon {k}");
            assert_eq!(fast.counts, slow.counts, "polygon {k}");
            assert_eq!(fast.keys, slow.keys, "polygon {k}");
            assert_eq!(fast.keys.len(), if ordered { fast.polys.len() } else { 0 }, "polygon {k}");
            compared += usize::from(!fast.polys.is_empty());
            small += fast.small.len() + fast.small_textured.len();
            textured += fast.small_textured.len();
        }
        assert!(compared > 1000, "only {compared} polygons drawn and compared");
        // The whole mesh in one run against the clipper path polygon after polygon into one batch.
        let (mut all_fast, mut all_slow) = (Batch::default(), Batch::default());
        setup.run(0..mesh.polygons().len(), &mut all_fast, &mut SetupScratch::default());
        for poly in mesh.polygons() {
            let (idx, material) = (mesh.polygon_indices(poly), &mesh.materials()[poly.material as usize]);
            let first = all_slow.screen.len();
            match setup.gather_clipped(idx, material, &mut all_slow, &mut SetupScratch::default()) {
                Some(g) => setup.finish(
                    first,
                    g,
                    (material, &setup.material_setup(poly.material, material)),
                    &mut all_slow,
                    &mut SetupScratch::default(),
                ),
                None => all_slow.screen.truncate(first),
            }
        }
        assert_eq!(screen_bits(&all_fast.screen), screen_bits(&all_slow.screen));
        assert_eq!(all_fast.small, all_slow.small);
        assert_eq!(all_fast.small_textured, all_slow.small_textured);
        assert_eq!(all_fast.polys, all_slow.polys);
        assert_eq!(all_fast.keys, all_slow.keys);
        assert_eq!(all_fast.counts, all_slow.counts);
        assert!(all_fast.polys.len() > 1000);
        assert!(small > 300, "only {small} small triangles set up");
        assert!(textures == 0 || textured > 100, "only {textured} textured small triangles set up");
    }
}
