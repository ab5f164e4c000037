//! Synthetic scenes shared by `cargo bench` and `examples/small_scene.rs`.

use glam::{Mat4, Vec2, Vec3, Vec4};
use scanline_racer::render::{Camera, Material, Mesh, MeshBuilder, Projection, Vertex};

/// A camera looking down -z whose x and y units are pixels of a `w` x `h` frame.
pub fn ortho(w: usize, h: usize) -> Camera {
    let (hw, hh) = (w as f32 * 0.5, h as f32 * 0.5);
    Camera {
        view: Mat4::from_translation(Vec3::new(-hw, -hh, -1000.0)),
        projection: Projection::Orthographic { xmag: hw, ymag: hh, znear: 1.0, zfar: 3000.0 },
    }
}

/// A mesh of flat triangles `(x, y, z)` in pixels, colours cycling.
pub fn triangles(tris: &[[Vec3; 3]]) -> Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { double_sided: true, ..Material::default() });
    for (i, t) in tris.iter().enumerate() {
        let c = Vec4::new((i % 7) as f32 / 7.0, (i % 5) as f32 / 5.0, (i % 3) as f32 / 3.0, 1.0);
        let idx: Vec<u32> = t.iter().map(|&p| b.vertex(Vertex { position: p, uv: Vec2::ZERO, color: c })).collect();
        b.polygon(&idx, m);
    }
    b.build().unwrap()
}

/// The small-polygon scene: a 200 x 100 grid of 3x3-pixel right triangles (about 4.5 pixels each) over
/// 640x480, at random depths.
pub fn small_triangles() -> Vec<[Vec3; 3]> {
    let mut small = vec![];
    let mut seed = 1u32;
    for gy in 0..100 {
        for gx in 0..200 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let z = (seed >> 8) as f32 / 16_777_216.0 * 100.0;
            let (x, y) = (gx as f32 * 3.2, gy as f32 * 4.8);
            small.push([Vec3::new(x, y, z), Vec3::new(x + 3.0, y, z), Vec3::new(x, y + 3.0, z)]);
        }
    }
    small
}
