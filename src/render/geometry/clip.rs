//! Clipping in homogeneous clip space: the near (and far) plane exactly, x and y against a guard band.
//!
//! A polygon crossing the near plane is cut there (Sutherland-Hodgman, one plane at a time); one wholly behind
//! it, or wholly outside any side of the view volume, is rejected. Sides are not clipped at the frame edge:
//! only polygons reaching past a guard band of [`GUARD_PIXELS`] beyond the frame are cut, so ordinary
//! polygons keep their exact vertices and the span stage scissors the rest. After this stage every vertex
//! projects to within the guard band, so its snapped [`crate::render::core::fixed::Fx28_4`] position cannot overflow.

use glam::Vec4;

/// Attributes carried through clipping: `u, v, r, g, b, a, view depth`.
pub const CLIP_ATTRS: usize = 7;

/// Index of the view-space depth in [`ClipVertex::attrs`].
pub const VIEW_DEPTH: usize = 6;

/// How far beyond each frame edge, in pixels, a polygon may reach before it is clipped.
pub const GUARD_PIXELS: f32 = 8192.0;

/// A vertex in clip space with the attributes that are interpolated when it is cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVertex {
    /// Clip-space position.
    pub pos: Vec4,
    /// Texture coordinate, colour and view depth, see [`CLIP_ATTRS`].
    pub attrs: [f32; CLIP_ATTRS],
}

/// The planes a polygon is tested and clipped against for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipVolume {
    /// Guard band half-extent in NDC units along x (`1 + 2 * GUARD_PIXELS / width`).
    pub guard_x: f32,
    /// The same along y.
    pub guard_y: f32,
    /// Whether the far plane `z <= w` is clipped (not for an infinite perspective).
    pub far: bool,
}

impl ClipVolume {
    /// The clip volume for a frame of `width` x `height` pixels.
    #[must_use]
    pub fn new(width: usize, height: usize, far: bool) -> Self {
        let g = |n: usize| 1.0 + 2.0 * GUARD_PIXELS / n.max(1) as f32;
        Self { guard_x: g(width), guard_y: g(height), far }
    }

    /// Signed distances to the planes: near, far, then the guard sides; positive is inside.
    fn distances(&self, p: Vec4) -> [f32; 6] {
        [
            p.z + p.w,
            if self.far { p.w - p.z } else { 1.0 },
            p.x + self.guard_x * p.w,
            self.guard_x * p.w - p.x,
            p.y + self.guard_y * p.w,
            self.guard_y * p.w - p.y,
        ]
    }
}

/// What happened to a polygon in clipping.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipResult {
    /// Wholly inside the guard band and in front of the near plane: unchanged.
    Inside,
    /// Cut by at least one plane; the output holds the clipped polygon.
    Clipped,
    /// Wholly outside the view volume, or nothing left after clipping.
    Outside,
}

/// Where one vertex lies against the clip volume, as two sets of bits (one per plane: near, far, then the
/// sides): a polygon is rejected when its vertices share a bit of `outside`, and must be cut when any of
/// them has a bit of `cut`. Set-up computes these once per vertex, not once per polygon corner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexCodes {
    /// Outside the view volume proper (sides at the frame edge), per plane.
    pub outside: u8,
    /// Behind a clip plane (sides at the guard band), per plane.
    pub cut: u8,
}

impl ClipVolume {
    /// The clip codes of a vertex at clip-space position `p`.
    #[must_use]
    pub fn codes(&self, p: Vec4) -> VertexCodes {
        let mut outside = 0;
        outside |= u8::from(p.z < -p.w);
        outside |= u8::from(self.far && p.z > p.w) << 1;
        outside |= u8::from(p.x < -p.w) << 2;
        outside |= u8::from(p.x > p.w) << 3;
        outside |= u8::from(p.y < -p.w) << 4;
        outside |= u8::from(p.y > p.w) << 5;
        let mut cut = 0;
        for (i, d) in self.distances(p).iter().enumerate() {
            cut |= u8::from(*d < 0.0) << i;
        }
        VertexCodes { outside, cut }
    }
}

/// Clips a polygon into `out` (cleared first), using `scratch` as working space.
///
/// Vertices must be finite; the caller drops polygons with NaN or infinite coordinates before this.
pub fn clip_polygon(
    input: &[ClipVertex],
    volume: &ClipVolume,
    out: &mut Vec<ClipVertex>,
    scratch: &mut Vec<ClipVertex>,
) -> ClipResult {
    out.clear();
    let (mut all, mut need) = (u8::MAX, 0u8);
    for v in input {
        let c = volume.codes(v.pos);
        all &= c.outside;
        need |= c.cut;
    }
    if all != 0 {
        return ClipResult::Outside;
    }
    out.extend_from_slice(input);
    if need == 0 {
        return ClipResult::Inside;
    }
    for plane in 0..6 {
        if need & (1 << plane) == 0 {
            continue;
        }
        std::mem::swap(out, scratch);
        out.clear();
        let n = scratch.len();
        for i in 0..n {
            let a = scratch[i];
            let b = scratch[if i + 1 == n { 0 } else { i + 1 }];
            let da = volume.distances(a.pos)[plane];
            let db = volume.distances(b.pos)[plane];
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                let mut attrs = [0.0; CLIP_ATTRS];
                for (k, v) in attrs.iter_mut().enumerate() {
                    *v = a.attrs[k] + t * (b.attrs[k] - a.attrs[k]);
                }
                out.push(ClipVertex { pos: a.pos + t * (b.pos - a.pos), attrs });
            }
        }
        if out.len() < 3 {
            out.clear();
            return ClipResult::Outside;
        }
    }
    ClipResult::Clipped
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cv(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex { pos: Vec4::new(x, y, z, w), attrs: [0.0; CLIP_ATTRS] }
    }

    #[test]
    fn near_plane_cuts_and_rejects() {
        let vol = ClipVolume::new(100, 100, true);
        let (mut out, mut s) = (vec![], vec![]);
        // Triangle with one vertex behind the near plane (z < -w): cut into a quad.
        let tri = [cv(0.0, 0.0, 0.0, 1.0), cv(0.5, 0.0, 0.0, 1.0), cv(0.0, 0.5, -3.0, 1.0)];
        assert_eq!(clip_polygon(&tri, &vol, &mut out, &mut s), ClipResult::Clipped);
        assert_eq!(out.len(), 4);
        assert!(out.iter().all(|v| v.pos.z + v.pos.w >= -1e-6));
        // Wholly behind: rejected.
        let behind = [cv(0.0, 0.0, -2.0, 1.0), cv(0.5, 0.0, -2.0, 1.0), cv(0.0, 0.5, -3.0, 1.0)];
        assert_eq!(clip_polygon(&behind, &vol, &mut out, &mut s), ClipResult::Outside);
        // Wholly right of the view: rejected without clipping.
        let right = [cv(2.0, 0.0, 0.0, 1.0), cv(3.0, 0.0, 0.0, 1.0), cv(2.0, 0.5, 0.0, 1.0)];
        assert_eq!(clip_polygon(&right, &vol, &mut out, &mut s), ClipResult::Outside);
        // Inside the guard band: untouched even though it leaves the frame.
        let wide = [cv(-50.0, 0.0, 0.0, 1.0), cv(1.5, 0.0, 0.0, 1.0), cv(0.0, 0.5, 0.0, 1.0)];
        assert_eq!(clip_polygon(&wide, &vol, &mut out, &mut s), ClipResult::Inside);
        // Far beyond it: cut to the guard band.
        let huge = [cv(-1e30, 0.0, 0.0, 1.0), cv(1.5, 0.0, 0.0, 1.0), cv(0.0, 0.5, 0.0, 1.0)];
        assert_eq!(clip_polygon(&huge, &vol, &mut out, &mut s), ClipResult::Clipped);
        assert!(out.iter().all(|v| v.pos.x.abs() <= vol.guard_x * v.pos.w * 1.0001));
    }
}
