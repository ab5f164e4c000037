//! The vertex transform: every vertex of an object to clip space, its view depth, its clip codes and (when
//! it needs no clipping) its snapped screen position, once per vertex however many polygons share it.
//!
//! [`VertexTransform::vertex`] is the reference, one vertex at a time, with the matrix product and the
//! depth's dot product written out in a fixed order: glam's, so each record is bit for bit what glam's own
//! product gives (a test holds it to that). Where the CPU has AVX2, [`VertexTransform::run`] takes eight
//! vertices per step instead ([`crate::render::geometry::transform_avx2`]): the same IEEE operations in the
//! same order, so the records are bit-identical (a test compares the two on random and hostile positions).

use super::vertex::{SetupVertex, VertexTransform};
use crate::render::core::mesh::Vertex;
use crate::render::simd;

impl VertexTransform {
    /// Transforms `vs` into `out` (as many as the shorter holds).
    pub(crate) fn run(&self, out: &mut [SetupVertex], vs: &[Vertex]) {
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = simd::avx2() {
            done = crate::render::geometry::transform_avx2::run(avx2, self, out, vs);
        }
        for (o, v) in out.iter_mut().zip(vs).skip(done) {
            *o = self.vertex(v.position);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::test_rng::Lcg;
    use crate::render::geometry::clip::ClipVolume;
    use crate::render::simd::force_portable;
    use glam::{Mat4, Vec3};
    use glam::{Quat, Vec2};

    /// A random coordinate of any scale; when `hostile`, one in sixteen is NaN, infinite, huge or zero.
    fn coord(rng: &mut Lcg, hostile: bool) -> f32 {
        match rng.below(16) {
            0 if hostile => [f32::NAN, f32::INFINITY, -f32::INFINITY, 3e30, -3e30, 0.0][rng.below(6) as usize],
            1 => 0.0,
            _ => (rng.next() as f32 / u32::MAX as f32 - 0.5) * [2.0, 40.0, 400.0, 1e5][rng.below(4) as usize],
        }
    }

    use crate::render::core::camera::{Camera, Projection};

    fn run(t: &VertexTransform, vs: &[Vertex], portable: bool) -> Vec<SetupVertex> {
        let mut out = vec![SetupVertex::default(); vs.len()];
        force_portable(portable);
        t.run(&mut out, vs);
        force_portable(false);
        out
    }

    #[test]
    fn eight_lanes_match_the_one_vertex_loop_bit_for_bit() {
        let mut rng = Lcg(11);
        let mut projected = 0;
        for case in 0..400 {
            let hostile = case % 3 == 2;
            let (w, h) = ([640usize, 1280, 1, 333][case % 4], [480usize, 720, 1, 77][(case / 4) % 4]);
            let projection = if case % 5 == 4 {
                Projection::Orthographic { xmag: 30.0, ymag: 20.0, znear: 0.5, zfar: 500.0 }
            } else {
                Projection::Perspective { yfov: 1.0, aspect: None, znear: 0.1, zfar: (case % 2 == 0).then_some(300.0) }
            };
            let eye = Vec3::new(coord(&mut rng, false), coord(&mut rng, false), coord(&mut rng, false) + 5.0);
            let view = Mat4::from_rotation_x(rng.next() as f32 * 1e-4) * Mat4::from_translation(-eye);
            let camera = Camera { view, projection };
            let model = Mat4::from_scale_rotation_translation(
                Vec3::splat(0.5 + (rng.next() % 4) as f32),
                Quat::from_rotation_y(rng.next() as f32 * 1e-3),
                Vec3::new(coord(&mut rng, false), 0.0, coord(&mut rng, false)),
            );
            let view_from_model = camera.view * model;
            let t = VertexTransform {
                clip_from_model: camera.clip_from_view(w, h) * camera.view * model,
                depth_row: view_from_model.row(2),
                volume: ClipVolume::new(w, h, camera.has_far_plane()),
                size: (w as f32, h as f32),
                perspective: camera.is_perspective(),
            };
            let n = (rng.next() % 40) as usize;
            let vs: Vec<Vertex> = (0..n)
                .map(|_| {
                    Vertex::new(
                        Vec3::new(coord(&mut rng, hostile), coord(&mut rng, hostile), coord(&mut rng, hostile)),
                        Vec2::ZERO,
                    )
                })
                .collect();
            let (fast, slow) = (run(&t, &vs, false), run(&t, &vs, true));
            for (i, (a, b)) in fast.iter().zip(&slow).enumerate() {
                assert_eq!(a.bits(), b.bits(), "case {case}, vertex {i} at {:?}", vs[i].position);
            }
            // The reference is SetupVertex::new on glam's own product, bit for bit.
            for (v, s) in vs.iter().zip(&slow) {
                let p = v.position.extend(1.0);
                let glam =
                    SetupVertex::new(t.clip_from_model * p, -t.depth_row.dot(p), &t.volume, t.size, t.perspective);
                assert_eq!(s.bits(), glam.bits(), "case {case} at {:?}", v.position);
            }
            projected += slow.iter().filter(|s| s.is_projected()).count();
        }
        assert!(projected > 1000, "only {projected} vertices projected");
    }
}
