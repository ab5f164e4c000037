//! The camera: where the eye is and how the view is projected, with glTF's conventions.
//!
//! View space looks down `-Z` with `+Y` up, as glTF cameras do. Clip space is OpenGL's: a point is inside
//! the view volume when `-w <= x, y, z <= w`. The viewport maps NDC `x = -1` to the left edge of the frame
//! and `y = +1` to the top; pixel centres sit at `i + 0.5`.

use glam::{Mat4, Vec3};

/// How view space is projected to clip space (glTF `camera.perspective` / `camera.orthographic`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// A pinhole camera.
    Perspective {
        /// Vertical field of view in radians.
        yfov: f32,
        /// Width / height of the view; the frame's own aspect when `None`.
        aspect: Option<f32>,
        /// Distance to the near plane (> 0).
        znear: f32,
        /// Distance to the far plane; infinite when `None`.
        zfar: Option<f32>,
    },
    /// A parallel projection.
    Orthographic {
        /// Half the width of the view volume.
        xmag: f32,
        /// Half the height of the view volume.
        ymag: f32,
        /// Distance to the near plane.
        znear: f32,
        /// Distance to the far plane.
        zfar: f32,
    },
}

/// A camera: the world-to-view transform and the projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// World space to view space (the inverse of the camera node's world transform).
    pub view: Mat4,
    /// The projection.
    pub projection: Projection,
}

impl Camera {
    /// A perspective camera at `eye` looking at `target` with `+Y` up.
    #[must_use]
    pub fn look_at(eye: Vec3, target: Vec3, yfov: f32, znear: f32, zfar: Option<f32>) -> Self {
        let up =
            if (target - eye).normalize_or_zero().cross(Vec3::Y).length_squared() < 1e-8 { Vec3::Z } else { Vec3::Y };
        Self {
            view: glam::camera::rh::view::look_at_mat4(eye, target, up),
            projection: Projection::Perspective { yfov, aspect: None, znear, zfar },
        }
    }

    /// The view-to-clip matrix for a frame of `width` x `height` pixels (the glTF projection matrices).
    #[must_use]
    pub fn clip_from_view(&self, width: usize, height: usize) -> Mat4 {
        let frame_aspect = if width > 0 && height > 0 { width as f32 / height as f32 } else { 1.0 };
        match self.projection {
            Projection::Perspective { yfov, aspect, znear, zfar } => {
                let aspect = aspect.filter(|a| a.is_finite() && *a > 0.0).unwrap_or(frame_aspect);
                // The glTF specification's matrices, written out so hostile values give NaN, never a panic.
                let f = 1.0 / libm::tanf(0.5 * yfov);
                let (c22, c32) = match zfar {
                    Some(zfar) => ((zfar + znear) / (znear - zfar), 2.0 * zfar * znear / (znear - zfar)),
                    None => (-1.0, -2.0 * znear),
                };
                Mat4::from_cols_array(&[
                    f / aspect,
                    0.0,
                    0.0,
                    0.0, //
                    0.0,
                    f,
                    0.0,
                    0.0, //
                    0.0,
                    0.0,
                    c22,
                    -1.0, //
                    0.0,
                    0.0,
                    c32,
                    0.0,
                ])
            }
            Projection::Orthographic { xmag, ymag, znear, zfar } => {
                let r = 1.0 / (znear - zfar);
                Mat4::from_cols_array(&[
                    1.0 / xmag,
                    0.0,
                    0.0,
                    0.0, //
                    0.0,
                    1.0 / ymag,
                    0.0,
                    0.0, //
                    0.0,
                    0.0,
                    2.0 * r,
                    0.0, //
                    0.0,
                    0.0,
                    (zfar + znear) * r,
                    1.0,
                ])
            }
        }
    }

    /// True for a perspective camera (depth is `1/w`), false for orthographic (depth is NDC `z`).
    #[must_use]
    pub fn is_perspective(&self) -> bool {
        matches!(self.projection, Projection::Perspective { .. })
    }

    /// True when a far plane exists and must be clipped against.
    #[must_use]
    pub fn has_far_plane(&self) -> bool {
        !matches!(self.projection, Projection::Perspective { zfar: None, .. })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn infinite_perspective_maps_near_plane_to_minus_one() {
        let c = Camera {
            view: Mat4::IDENTITY,
            projection: Projection::Perspective { yfov: 1.0, aspect: Some(1.0), znear: 0.5, zfar: None },
        };
        let p = c.clip_from_view(10, 10) * Vec4::new(0.0, 0.0, -0.5, 1.0);
        assert!((p.z / p.w + 1.0).abs() < 1e-6);
        let far = c.clip_from_view(10, 10) * Vec4::new(0.0, 0.0, -1e6, 1.0);
        assert!(far.z / far.w < 1.0);
    }

    #[test]
    fn orthographic_maps_near_and_far() {
        let c = Camera {
            view: Mat4::IDENTITY,
            projection: Projection::Orthographic { xmag: 2.0, ymag: 1.0, znear: 1.0, zfar: 3.0 },
        };
        let m = c.clip_from_view(4, 2);
        let n = m * Vec4::new(2.0, 1.0, -1.0, 1.0);
        let f = m * Vec4::new(-2.0, -1.0, -3.0, 1.0);
        assert!((n - Vec4::new(1.0, 1.0, -1.0, 1.0)).abs().max_element() < 1e-6);
        assert!((f - Vec4::new(-1.0, -1.0, 1.0, 1.0)).abs().max_element() < 1e-6);
    }
}
