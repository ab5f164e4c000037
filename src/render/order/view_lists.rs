//! Orders made in advance (seed 004, Canon EP 0 612 031): for each rigid mesh and each of a fixed set of
//! view directions, a drawing order computed once by a topological sort of 'may occlude' relations; at run
//! time the list of the nearest stored direction is drawn as is, and whole objects are placed with the
//! ordering table (by the nearest depth of their bounding sphere, when seen from at least twice its radius;
//! nearer than that, or for meshes without lists, polygons are ordered one by one as in `bucket-far`).
//!
//! Building one list (direction `d`, depth = `p·d`, larger is farther): a *favourite* polygon, at first the
//! farthest not yet placed, is compared with every candidate not yet placed. A candidate the favourite may
//! occlude (their projections along `d` overlap and the favourite is in front somewhere) must be drawn
//! first: it *prevents* the favourite, so the favourite goes on a last-in-first-out stack of favourites and
//! the candidate becomes the favourite. A favourite nothing prevents is appended to the list, and the last
//! favourite on the stack is taken up again. A candidate that is already on the stack closes a cycle (three
//! planks over each other, or two polygons that intersect): the cycle is broken by splitting one polygon of
//! it by the other's plane, and the pieces go back among the candidates.
//!
//! 'May occlude' is decided conservatively, as Newell, Newell and Sancha did: projections that do not
//! overlap (separating axis on their convex hulls) cannot; otherwise P may be in front of Q unless Q lies
//! wholly on the viewer's side of P's plane or P wholly beyond Q's plane.
//!
//! Directions are the vertices of an icosahedron subdivided `level` times (12, 42, 162, 642 directions):
//! evenly spread, so the angle from any view to the nearest stored direction is bounded: at worst 37°, 21°
//! and 11° at levels 0, 1 and 2 (a test checks these bounds). The bench charts the error against the level.

mod occlusion;

use glam::{Mat4, Vec3};

use crate::render::core::camera::Camera;
use crate::render::core::draw_list::{MeshLists, ViewLists};
use crate::render::core::mesh::Mesh;

/// Meshes of at most this many polygons get orders made in advance by default: cars, trees, buildings;
/// not whole-world road and terrain meshes, which are not rigid objects seen from outside.
pub const DEFAULT_MAX_POLYGONS: usize = 600;
/// Default icosahedron subdivision level of the stored directions: 42 directions, no view more than 21°
/// from one (37° with 12): finer than the demo race's own views need, for the views it does not show, and
/// coarser than 162, which costs more time for little accuracy (the bench compares levels 0-2).
pub const DEFAULT_LEVEL: u32 = 1;

/// The view directions of an icosahedron subdivided `level` times (unit vectors, deterministic order).
#[must_use]
pub fn directions(level: u32) -> Vec<Vec3> {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut verts: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level.min(4) {
        let mut mid = std::collections::BTreeMap::new();
        let mut next = Vec::with_capacity(faces.len() * 4);
        let mut midpoint = |a: usize, b: usize, verts: &mut Vec<Vec3>| -> usize {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push((verts[a] + verts[b]).normalize());
                verts.len() - 1
            })
        };
        for [a, b, c] in faces {
            let ab = midpoint(a, b, &mut verts);
            let bc = midpoint(b, c, &mut verts);
            let ca = midpoint(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    verts
}

impl ViewLists {
    /// Builds lists for every mesh of at most `max_polygons` polygons, for the directions of `level`.
    #[must_use]
    pub fn build(meshes: &[Mesh], level: u32, max_polygons: usize) -> Self {
        let dirs = directions(level);
        Self {
            meshes: meshes
                .iter()
                .map(|m| (m.polygons().len() <= max_polygons).then(|| occlusion::build_mesh(m, &dirs)).flatten())
                .collect(),
        }
    }
}

/// The stored order to draw `lists`' mesh in, placed by `model`, with the key that places the whole object
/// in the ordering table; `None` when the object is to be ordered polygon by polygon.
///
/// A stored order is for an object seen from outside: from at least twice its radius away. A mesh the
/// camera is in or near (a stretch of road, the terrain) is ordered per polygon instead. The object is
/// placed by the nearest depth of its bounding sphere (`center`, `radius`, in world space), so it is drawn
/// after the ground polygons it stands on (with its centre's depth, big road polygons near the camera
/// painted over the lower half of the player's car).
#[must_use]
pub(crate) fn stored_order<'a>(
    lists: &'a MeshLists,
    model: &Mat4,
    (center, radius): (Vec3, f32),
    camera: &Camera,
    (eye, forward): (Vec3, Vec3),
) -> Option<(&'a [u32], f32)> {
    let outside = (center - eye).length() > 2.0 * radius;
    if !outside {
        return None;
    }
    let to_object = if camera.is_perspective() { Ok(eye) } else { Err(forward) };
    let d = model_direction(model, center, to_object)?;
    Some((lists.nearest(d), -camera.view.transform_point3(center).z - radius))
}

/// The direction from `eye` to an object's centre in the object's model space, or `None` when it is not
/// defined (eye at the centre, a singular model matrix).
#[must_use]
pub fn model_direction(model: &Mat4, center_world: Vec3, eye_or_forward: Result<Vec3, Vec3>) -> Option<Vec3> {
    let world_dir = match eye_or_forward {
        Ok(eye) => center_world - eye,
        Err(forward) => forward,
    };
    let inv = model.inverse();
    let d = inv.transform_vector3(world_dir);
    let len = d.length();
    (len > 0.0 && len.is_finite()).then(|| d / len)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_unit_and_spread() {
        // Worst angle from any view to the nearest stored direction, over 20,000 evenly spread views.
        let views: Vec<Vec3> = (0..20_000)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 20_000.0;
                let r = (1.0 - z * z).sqrt();
                let a = i as f32 * 2.399_963;
                Vec3::new(r * libm::cosf(a), r * libm::sinf(a), z)
            })
            .collect();
        for (level, n, worst_deg) in [(0, 12, 37.5), (1, 42, 21.0), (2, 162, 11.0)] {
            let d = directions(level);
            assert_eq!(d.len(), n);
            assert!(d.iter().all(|v| (v.length() - 1.0).abs() < 1e-5));
            let worst = views
                .iter()
                .map(|v| libm::acosf(d.iter().map(|s| s.dot(*v)).fold(-1.0f32, f32::max).clamp(-1.0, 1.0)).to_degrees())
                .fold(0.0f32, f32::max);
            assert!(worst <= worst_deg && worst > worst_deg - 2.0, "level {level}: worst {worst} degrees");
        }
    }
}
