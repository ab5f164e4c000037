//! One vertex after the transform: the record the transform writes for set-up, and the one-vertex
//! transform that is the reference of the vector loop.

use glam::{Mat4, Vec3, Vec4};

use crate::render::core::fixed::Fx28_4;
use crate::render::geometry::clip::ClipVolume;
#[cfg(test)]
use crate::render::geometry::clip::VertexCodes;

/// A [`SetupVertex`] as bits: view depth, codes, finite, and screen `(x, y, depth, 1/w)` if projected.
#[cfg(test)]
pub(crate) type SetupBits = (u32, VertexCodes, bool, Option<(i32, i32, u32, u32)>);

/// One vertex of an object after the transform: its clip codes and, when it needs no clipping, its snapped
/// screen position, so a polygon wholly inside the guard band is set up by gathering its corners (computed
/// once per vertex, however many polygons share it) without going through the clipper.
///
/// The record is 24 bytes: the clip position is not kept (a polygon that needs clipping recomputes its
/// corners' positions, [`VertexTransform::clip_and_depth`]), so the transform writes, and set-up reads, half
/// as much as with it. It is plain old data (`repr(C)`, flags as bytes) so that the AVX2 transform writes
/// eight of them with vector stores rather than field by field.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct SetupVertex {
    /// Snapped screen x and y (raw [`Fx28_4`]), depth and `1/w` when `projected`, zeros otherwise.
    x: i32,
    y: i32,
    depth: f32,
    q: f32,
    /// View depth (distance along the view direction), for ordering keys.
    pub(crate) view_depth: f32,
    /// Where it lies against the clip planes ([`VertexCodes`](crate::render::geometry::clip::VertexCodes)).
    pub(crate) outside: u8,
    pub(crate) cut: u8,
    /// 1 when the clip position and the view depth are finite, else 0.
    finite: u8,
    /// 1 when the vertex is finite, inside every clip plane and projects onto the grid, else 0.
    projected: u8,
}

// The AVX2 transform writes a record as six words in this order (`transform_avx2.rs`).
const _: () = {
    use std::mem::offset_of;
    assert!(size_of::<SetupVertex>() == 24);
    assert!(offset_of!(SetupVertex, x) == 0 && offset_of!(SetupVertex, y) == 4);
    assert!(offset_of!(SetupVertex, depth) == 8 && offset_of!(SetupVertex, q) == 12);
    assert!(offset_of!(SetupVertex, view_depth) == 16 && offset_of!(SetupVertex, outside) == 20);
    assert!(offset_of!(SetupVertex, cut) == 21 && offset_of!(SetupVertex, finite) == 22);
    assert!(offset_of!(SetupVertex, projected) == 23);
};

impl SetupVertex {
    /// Tests and projects a vertex at clip position `pos` with view depth `view_depth`.
    #[inline(always)]
    pub(crate) fn new(pos: Vec4, view_depth: f32, volume: &ClipVolume, size: (f32, f32), perspective: bool) -> Self {
        let finite = pos.is_finite() && view_depth.is_finite();
        let codes = volume.codes(pos);
        let screen = if finite && codes.cut == 0 { project(pos, size, perspective) } else { None };
        let (x, y, depth, q) = screen.unwrap_or((Fx28_4(0), Fx28_4(0), 0.0, 0.0));
        Self {
            x: x.0,
            y: y.0,
            depth,
            q,
            view_depth,
            outside: codes.outside,
            cut: codes.cut,
            finite: u8::from(finite),
            projected: u8::from(screen.is_some()),
        }
    }

    /// The snapped screen position, depth and `1/w` (zeros when the vertex did not project).
    #[inline(always)]
    pub(crate) fn screen_or_zero(&self) -> (Fx28_4, Fx28_4, f32, f32) {
        (Fx28_4(self.x), Fx28_4(self.y), self.depth, self.q)
    }

    /// The snapped screen position, depth and `1/w`, if the vertex projected.
    #[inline]
    pub(crate) fn screen(&self) -> Option<(Fx28_4, Fx28_4, f32, f32)> {
        self.is_projected().then_some(self.screen_or_zero())
    }

    /// Where it lies against the clip planes.
    #[cfg(test)]
    pub(crate) fn codes(&self) -> VertexCodes {
        VertexCodes { outside: self.outside, cut: self.cut }
    }

    /// The mask of [`Self::flags`] over the bytes `outside`, `finite` and `projected`.
    pub(crate) const FINITE_PROJECTED_OUTSIDE: u32 = 0x0101_00ff;
    /// [`Self::flags`] of a vertex that is finite and projected and outside no clip plane.
    pub(crate) const FINITE_PROJECTED: u32 = 0x0101_0000;
    /// The mask of [`Self::flags`] over the byte `cut`.
    pub(crate) const CUT: u32 = 0x0000_ff00;

    /// The four flag bytes as one word, `outside` lowest, then `cut`, `finite` and `projected`: one load
    /// where the small-triangle set-up tests three corners at once.
    #[inline(always)]
    pub(crate) fn flags(&self) -> u32 {
        u32::from_le_bytes([self.outside, self.cut, self.finite, self.projected])
    }

    /// Whether the clip position and the view depth are finite.
    #[inline(always)]
    pub(crate) fn is_finite(&self) -> bool {
        self.finite != 0
    }

    /// Whether the vertex has a screen position.
    #[inline(always)]
    pub(crate) fn is_projected(&self) -> bool {
        self.projected != 0
    }

    /// Every field as bits, to compare records exactly; every NaN is one value (the sign and payload of a
    /// NaN depend on operand order, which the compiler may swap, and no frame depends on them: a vertex with
    /// one is never drawn).
    #[cfg(test)]
    pub(crate) fn bits(&self) -> SetupBits {
        let b = |v: f32| if v.is_nan() { f32::NAN.to_bits() } else { v.to_bits() };
        let screen = self.screen().map(|(x, y, d, q)| (x.0, y.0, b(d), b(q)));
        (b(self.view_depth), self.codes(), self.is_finite(), screen)
    }
}

/// Projects a clip-space position to the snapped screen position, its depth and `1/w`; `None` when it
/// does not land on the fixed-point grid or is not in front of the camera.
#[inline]
pub(crate) fn project(p: Vec4, size: (f32, f32), perspective: bool) -> Option<(Fx28_4, Fx28_4, f32, f32)> {
    let q = 1.0 / p.w;
    let sx = (p.x * q + 1.0) * 0.5 * size.0;
    let sy = (1.0 - p.y * q) * 0.5 * size.1;
    let (x, y) = (Fx28_4::from_f32(sx)?, Fx28_4::from_f32(sy)?);
    if !(p.w > 0.0 && q.is_finite()) {
        return None;
    }
    let depth = if perspective { q } else { 0.5 * (1.0 - p.z * q) };
    Some((x, y, depth, q))
}

/// What turns an object's model-space positions into [`SetupVertex`] records for one frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct VertexTransform {
    /// Model to clip space.
    pub(crate) clip_from_model: Mat4,
    /// The row of the model-to-view matrix that gives view z (the view depth is its negation).
    pub(crate) depth_row: Vec4,
    /// The clip volume.
    pub(crate) volume: ClipVolume,
    /// Frame width and height in pixels.
    pub(crate) size: (f32, f32),
    /// Perspective (depth is `1/w`) or orthographic camera.
    pub(crate) perspective: bool,
}

impl VertexTransform {
    /// The clip position and view depth of model position `p`, in the reference order of operations.
    #[inline(always)]
    pub(crate) fn clip_and_depth(&self, p: Vec3) -> (Vec4, f32) {
        let (m, d) = (&self.clip_from_model, self.depth_row);
        let row = |x: f32, y: f32, z: f32, w: f32| ((x * p.x + y * p.y) + z * p.z) + w;
        let pos = Vec4::new(
            row(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.w_axis.x),
            row(m.x_axis.y, m.y_axis.y, m.z_axis.y, m.w_axis.y),
            row(m.x_axis.z, m.y_axis.z, m.z_axis.z, m.w_axis.z),
            row(m.x_axis.w, m.y_axis.w, m.z_axis.w, m.w_axis.w),
        );
        (pos, -((d.x * p.x + d.z * p.z) + (d.y * p.y + d.w)))
    }

    /// One vertex, the reference the eight-lane path must match bit for bit.
    #[inline(always)]
    pub(crate) fn vertex(&self, p: Vec3) -> SetupVertex {
        let (pos, view_depth) = self.clip_and_depth(p);
        SetupVertex::new(pos, view_depth, &self.volume, self.size, self.perspective)
    }
}
