//! The z-buffer's coarse depth: frames with it and without it are the same bit for bit, on scenes of walls
//! with polygons behind, beside, across and in their planes, and it skips polygons (fewer pixels rejected).

use glam::{Mat4, Vec2, Vec3, Vec4};
use scanline_racer::render::{
    AlphaMode, Antialias, Camera, DrawList, Instance, Material, Mesh, MeshBuilder, Projection, RenderOptions, Renderer,
    Texture, Vertex,
};

use crate::common::Rng;

/// A quad of corners `centre ± u ± v` in material `m` and colour `c`, as one polygon or two triangles.
fn quad(b: &mut MeshBuilder, centre: Vec3, (u, v): (Vec3, Vec3), (m, c): (u32, Vec4), split: bool) {
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let idx: Vec<u32> = corners
        .iter()
        .map(|&(s, t)| b.vertex(Vertex { position: centre + u * s + v * t, uv: Vec2::new(s * 2.0, t * 2.0), color: c }))
        .collect();
    if split {
        b.polygon(&[idx[0], idx[1], idx[2]], m);
        b.polygon(&[idx[0], idx[2], idx[3]], m);
    } else {
        b.polygon(&idx, m);
    }
}

/// A random scene in front of a perspective camera at the origin looking down -z: big walls (some tilted,
/// some cut-outs, which hide nothing) and many polygons behind, beside, across and in the planes of the
/// walls (some decals lifted towards the eye by a depth bias), textured or flat; the walls drawn first, or
/// last when `walls_last`.
fn scene(rng: &mut Rng, walls_last: bool) -> Mesh {
    let mut b = MeshBuilder::new();
    let flat = b.material(Material { double_sided: true, ..Material::default() });
    let textured = b.material(Material { texture: Some(0), double_sided: true, ..Material::default() });
    let cut_out = b.material(Material {
        texture: Some(0),
        double_sided: true,
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    });
    let decal = b.material(Material { double_sided: true, depth_bias: 1, ..Material::default() });
    let colour = |rng: &mut Rng| Vec4::new(rng.unit(), rng.unit(), rng.unit(), 1.0);
    let mut walls = Vec::new();
    for _ in 0..1 + rng.range(0, 4) {
        let centre = Vec3::new(rng.unit() * 4.0 - 2.0, rng.unit() * 3.0 - 1.5, -3.0 - rng.unit() * 6.0);
        let tilt = rng.unit() * 0.8 - 0.4;
        let u = Vec3::new(1.0 + rng.unit() * 3.0, 0.0, tilt * 2.0);
        let v = Vec3::new(0.0, 1.0 + rng.unit() * 2.0, -tilt);
        let m = [flat, textured, textured, cut_out][rng.range(0, 4) as usize];
        let c = colour(rng);
        walls.push((centre, u, v, m, c, rng.range(0, 2) == 0));
    }
    let wall = |b: &mut MeshBuilder, &(centre, u, v, m, c, split): &(Vec3, Vec3, Vec3, u32, Vec4, bool)| {
        quad(b, centre, (u, v), (m, c), split)
    };
    if !walls_last {
        walls.iter().for_each(|w| wall(&mut b, w));
    }
    for i in 0..400 {
        let (wc, wu, wv, ..) = walls[i % walls.len()];
        let on_wall = wc + wu * (rng.unit() * 2.0 - 1.0) + wv * (rng.unit() * 2.0 - 1.0);
        let size = 0.02 + rng.unit() * [0.1, 0.5, 2.0][rng.range(0, 3) as usize];
        let (centre, m, u, v) = match rng.range(0, 6) {
            // In the wall's plane, a decal or not.
            0 => (on_wall, if rng.range(0, 2) == 0 { decal } else { flat }, wu * size * 0.3, wv * size * 0.3),
            // A hair behind the wall, or in front.
            1 => {
                let dz = [-1e-4, -1e-6, 1e-5][rng.range(0, 3) as usize];
                (on_wall + Vec3::new(0.0, 0.0, dz), flat, wu * 0.1, wv * 0.1)
            }
            // Across the wall.
            2 => (on_wall, textured, Vec3::new(size, 0.0, size * 4.0), Vec3::new(0.0, size, -size * 3.0)),
            // Behind it, on the same line of sight.
            _ => {
                let m = [flat, textured, cut_out][rng.range(0, 3) as usize];
                (on_wall * (1.0 + rng.unit() * 4.0), m, Vec3::X * size, Vec3::Y * size)
            }
        };
        let c = colour(rng);
        quad(&mut b, centre, (u, v), (m, c), rng.range(0, 2) == 0);
    }
    if walls_last {
        walls.iter().for_each(|w| wall(&mut b, w));
    }
    b.build().expect("a mesh")
}

#[test]
fn skipping_hidden_polygons_changes_no_pixel() {
    let mut rng = Rng(41);
    let texels: Vec<u32> =
        (0..64 * 64).map(|i| if (i / 8 + i / 512) % 2 == 0 { 0xff30_6090 } else { 0x40c0_a020 }).collect();
    let texture = Texture::new(64, 64, texels).expect("a texture");
    let (mut rejected_with, mut rejected_without) = (0, 0);
    let (mut written_with, mut written_without) = (0, 0);
    for case in 0..36 {
        let meshes = [scene(&mut rng, case % 4 >= 2)];
        let (w, h) = ([64usize, 161, 320][case % 3], [48usize, 97, 240][(case / 3) % 3]);
        let camera = Camera {
            view: Mat4::from_rotation_z(rng.unit() * 0.3 - 0.15),
            projection: Projection::Perspective { yfov: 1.0, aspect: None, znear: 0.5, zfar: Some(200.0) },
        };
        let (instances, textures) = ([Instance::new(0, Mat4::IDENTITY)], [texture.clone()]);
        let list =
            DrawList { meshes: &meshes, textures: &textures, instances: &instances, lod_sets: &[], view_lists: None };
        let antialias = [Antialias::Off, Antialias::RotatedGrid, Antialias::Supersample2x2][(case / 9) % 3];
        let threads = 1 + case % 2;
        let draw = |coarse_depth: bool| {
            let options = RenderOptions { threads, antialias, coarse_depth, ..RenderOptions::default() };
            let mut frame = vec![0u32; w * h];
            let stats = Renderer::new().render(&mut frame, w, h, &camera, &list, &options).expect("a frame");
            (frame, stats)
        };
        let ((a, with), (b, without)) = (draw(true), draw(false));
        assert!(
            a == b,
            "case {case}: {w}x{h}, {antialias:?}: {} pixels differ",
            a.iter().zip(&b).filter(|(x, y)| x != y).count()
        );
        // A polygon skipped before the one that hides it is drawn is not written (a pixel may be written
        // more often with it, by polygons between the two that skipping left nearer: counted over all).
        (written_with, written_without) =
            (written_with + with.pixels_written, written_without + without.pixels_written);
        (rejected_with, rejected_without) =
            (rejected_with + with.pixels_rejected, rejected_without + without.pixels_rejected);
    }
    // The hidden polygons' pixels are not rejected one by one: those drawn from their corners were skipped
    // whole (about a fifth of the pixels the depth test rejects here; small triangles are not tried).
    assert!(rejected_with * 6 < rejected_without * 5, "rejected {rejected_with} with, {rejected_without} without");
    // Floors come from the whole band before its first polygon: polygons drawn before the walls that hide
    // them (half the scenes draw their walls last) are skipped too.
    assert!(written_with < written_without, "{written_with} pixels written with, {written_without} without");
}
