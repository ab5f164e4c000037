//! The eight-lane set-up against the one-polygon loop, batch for batch.

use glam::{Vec2, Vec3, Vec4};

use crate::render::core::batch::Batch;
use crate::render::core::mesh::{Material, Mesh};
use crate::render::core::options::DepthKey;
use crate::render::core::polygon::FastPathRule;
use crate::render::core::test_rng::Lcg;
use crate::render::geometry::clip::ClipVolume;
use crate::render::geometry::setup::{ObjectSetup, SetupScratch};
use crate::render::geometry::vertex::VertexTransform;
use crate::render::simd::{force_portable, has_avx2};
use crate::render::{Camera, Filter, MeshBuilder, MipMode, Texture, TextureMode, Vertex};

/// A mesh of runs of polygons sharing a material (flat, tinted, textured, single- and double-sided): mostly
/// triangles of a fraction of a pixel to a few dozen pixels, some quads, some crossing the near plane or the
/// frame's edges, some with a NaN corner, corners of one colour or of several (one NaN after the tint).
fn mesh(rng: &mut Lcg) -> Mesh {
    let mut b = MeshBuilder::new();
    let tint = Vec4::new(0.9, 0.0, 0.25, 1.0);
    let materials = [
        b.material(Material { double_sided: true, ..Material::default() }),
        b.material(Material { base_color: tint, ..Material::default() }),
        b.material(Material { texture: Some(0), ..Material::default() }),
        b.material(Material { texture: Some(0), double_sided: true, ..Material::default() }),
    ];
    // Set-up takes an object to the lanes when its first polygon is flat: the mesh starts and ends with a
    // flat run (it is also set up in reverse order).
    let (mut polygons, total) = (0, 4000);
    while polygons < total {
        let ends = polygons == 0 || polygons > total - 30;
        let (material, run) = match ends {
            true => (materials[0], 30),
            false => (materials[rng.below(4) as usize], 1 + rng.below(40)),
        };
        for _ in 0..run {
            let corners = if rng.below(10) == 0 { 4 } else { 3 };
            // Sizes in pixels at depth `d`: from a tenth of a pixel to a few dozen; one in twenty near the
            // near plane (0.5), with a spread that crosses it.
            let d = if rng.below(20) == 0 { 0.6 } else { 1.0 + rng.unit() * 60.0 };
            let spread = [0.0003, 0.003, 0.01, 0.05, 2.0][rng.below(5) as usize] * d;
            let centre = Vec3::new((rng.unit() - 0.5) * 1.5 * d, (rng.unit() - 0.5) * 1.2 * d, -d);
            let flat = Vec4::new(rng.unit(), rng.unit(), rng.unit(), 1.0);
            let idx: Vec<u32> = (0..corners)
                .map(|_| {
                    let mut position =
                        centre + Vec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5) * spread;
                    if rng.below(200) == 0 {
                        position.x = f32::NAN;
                    }
                    let color = match rng.below(8) {
                        0 => Vec4::new(rng.unit(), rng.unit(), 0.5, 1.0),
                        1 => Vec4::new(flat.x, f32::INFINITY, flat.z, 1.0),
                        _ => flat,
                    };
                    b.vertex(Vertex { position, uv: Vec2::new(rng.unit() * 4.0, rng.unit() * 4.0), color })
                })
                .collect();
            b.polygon(&idx, material);
            polygons += 1;
        }
    }
    b.build().unwrap()
}

thread_local! {
    /// Groups of eight set up in the lanes on this thread.
    pub(super) static GROUPS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Sets up `range` of `setup`'s polygons, with the vector loops when `lanes`, and says how many groups of
/// eight went through the lanes.
fn run(setup: &ObjectSetup<'_>, range: std::ops::Range<usize>, lanes: bool) -> (Batch, usize) {
    force_portable(!lanes);
    GROUPS.with(|g| g.set(0));
    let mut out = Batch::default();
    setup.run(range, &mut out, &mut SetupScratch::default());
    force_portable(false);
    (out, GROUPS.with(std::cell::Cell::get))
}

// long: one scenario over the settings that change what set-up writes.
#[test]
fn the_eight_lane_set_up_writes_exactly_what_the_one_polygon_loop_writes() {
    if !has_avx2() {
        eprintln!("no AVX2 on this CPU: only the one-polygon loop exists");
        return;
    }
    let mut rng = Lcg(31);
    let mesh = mesh(&mut rng);
    let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, Some(100.0));
    let (w, h) = (320, 240);
    let texture = Texture::new(64, 32, vec![0x0080_4020; 64 * 32]).unwrap();
    let mut order: Vec<u32> = (0..mesh.polygons().len() as u32).collect();
    order.reverse();
    for (perspective, textures, mip, stored, ordered, tall) in [
        (true, 1, false, false, false, false),
        (false, 1, false, false, true, false),
        (true, 1, true, false, false, false),
        (true, 0, false, true, true, false),
        (true, 1, false, true, false, false),
        // A frame of four rows a pixel: the boxes widened by the rows' reach, in lanes and one by one.
        (true, 1, false, false, false, true),
    ] {
        let transform = VertexTransform {
            clip_from_model: camera.clip_from_view(w, h) * camera.view,
            depth_row: camera.view.row(2),
            volume: ClipVolume::new(w, h, true),
            size: (w as f32, h as f32),
            perspective,
        };
        let vertices: Vec<_> = mesh.vertices().iter().map(|v| transform.vertex(v.position)).collect();
        let mip_mode = if mip { MipMode::Polygon } else { MipMode::Off };
        let setup = ObjectSetup {
            mesh: &mesh,
            stored: stored.then_some(order.as_slice()),
            vertices: &vertices,
            transform: &transform,
            key: DepthKey::Avg,
            ordered,
            perspective_attrs: perspective,
            object_key: None,
            textures,
            door: crate::render::core::door::Door::NONE,
            mip_textures: if mip { std::slice::from_ref(&texture) } else { &[] },
            fast_path: FastPathRule { filter: Filter::Nearest, mode: TextureMode::Perspective, mip: mip_mode },
            antialiased: false,
            tall,
            width: w as i32,
        };
        // Every start, so that groups of eight begin at every offset of the material runs.
        for start in [0, 1, 3, 7] {
            let n = mesh.polygons().len();
            let ((fast, groups), (slow, none)) = (run(&setup, start..n, true), run(&setup, start..n, false));
            let case = format!(
                "perspective {perspective}, textures {textures}, mip {mip}, stored {stored}, tall {tall}, start {start}"
            );
            assert_eq!(fast.small, slow.small, "{case}");
            assert_eq!(fast.small_textured, slow.small_textured, "{case}");
            assert_eq!(fast.polys, slow.polys, "{case}");
            assert_eq!(fast.keys, slow.keys, "{case}");
            assert_eq!(fast.counts, slow.counts, "{case}");
            let bits = |b: &Batch| b.screen.iter().map(|v| (v.x, v.y, v.attrs.map(f32::to_bits))).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&slow), "{case}");
            // The lanes took part (in runs of flat triangles), and every kind of polygon they must hand back
            // or finish themselves is there.
            assert!(groups >= 20 && none == 0, "{case}: {groups} groups in lanes, {none} without them");
            let c = fast.counts;
            let small = (fast.small.len(), fast.small_textured.len());
            assert!(small.0 > 300 && (textures == 0 || small.1 > 300), "{case}: {small:?} {c:?}");
            assert!(c.backface > 300 && c.invalid > 10 && c.clipped > 10 && c.degenerate > 0, "{case}: {c:?}");
            assert!(fast.polys.len() > fast.small.len() + fast.small_textured.len() + 100, "{case}");
        }
    }
}
