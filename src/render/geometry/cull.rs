//! Object culling: a mesh instance whose bounding sphere lies wholly outside the view frustum is skipped
//! before any of its vertices are transformed.

use glam::{Mat4, Vec4};

use crate::render::core::mesh::Sphere;

/// The frustum planes of a clip-from-world matrix, normalised, inside positive.
#[derive(Clone, Copy, Debug)]
pub struct Frustum {
    planes: [Vec4; 6],
    count: usize,
}

impl Frustum {
    /// Extracts the planes of `clip_from_world` (Gribb and Hartmann); the far plane only when `far`.
    #[must_use]
    pub fn new(clip_from_world: &Mat4, far: bool) -> Self {
        let m = clip_from_world.transpose();
        let (r0, r1, r2, r3) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
        let mut planes = [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2];
        let mut count = if far { 6 } else { 5 };
        for p in planes.iter_mut().take(count) {
            let len = p.truncate().length();
            if len > 0.0 && len.is_finite() {
                *p /= len;
            } else {
                // A degenerate plane culls nothing.
                *p = Vec4::new(0.0, 0.0, 0.0, 1.0);
            }
        }
        if !planes.iter().take(count).all(|p| p.is_finite()) {
            count = 0;
        }
        Self { planes, count }
    }

    /// True when the sphere (already in world space) is wholly outside one of the planes.
    #[must_use]
    pub fn excludes(&self, center: glam::Vec3, radius: f32) -> bool {
        self.planes[..self.count].iter().any(|p| p.truncate().dot(center) + p.w < -radius)
    }
}

/// The world-space bounding sphere of a model-space sphere under `model` (radius scaled by the largest axis).
#[must_use]
pub fn world_sphere(s: Sphere, model: &Mat4) -> (glam::Vec3, f32) {
    world_sphere_scaled(s, model, model_scale(model))
}

/// The largest length of `model`'s three axes: the factor it scales a bounding sphere's radius by.
#[must_use]
pub fn model_scale(model: &Mat4) -> f32 {
    model.x_axis.truncate().length().max(model.y_axis.truncate().length()).max(model.z_axis.truncate().length())
}

/// [`world_sphere`] with `model`'s [`model_scale`] already known: the spheres of one instance's models share
/// it, and its three square roots are a good part of choosing and culling a model.
#[must_use]
pub fn world_sphere_scaled(s: Sphere, model: &Mat4, scale: f32) -> (glam::Vec3, f32) {
    (model.transform_point3(s.center), s.radius * scale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn spheres_behind_or_beside_are_excluded() {
        let proj = crate::render::Camera {
            view: Mat4::IDENTITY,
            projection: crate::render::Projection::Perspective {
                yfov: 1.0,
                aspect: Some(1.0),
                znear: 0.1,
                zfar: Some(100.0),
            },
        }
        .clip_from_view(1, 1);
        let f = Frustum::new(&proj, true);
        assert!(!f.excludes(Vec3::new(0.0, 0.0, -5.0), 1.0));
        assert!(f.excludes(Vec3::new(0.0, 0.0, 5.0), 1.0));
        assert!(f.excludes(Vec3::new(50.0, 0.0, -5.0), 1.0));
        assert!(!f.excludes(Vec3::new(3.0, 0.0, -5.0), 1.0));
        assert!(f.excludes(Vec3::new(0.0, 0.0, -200.0), 1.0));
    }
}
