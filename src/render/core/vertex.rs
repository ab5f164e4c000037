//! The screen vertex: a snapped position and the attributes interpolated across a polygon, as set-up hands
//! them to the fill.

use crate::render::core::fixed::Fx28_4;

/// Number of interpolated attributes per vertex.
pub const ATTRS: usize = 8;

/// Attribute slots in [`ScreenVertex::attrs`].
pub mod slot {
    /// Depth for the z-buffer, larger is nearer (`1/w` for perspective, `(1 - z_ndc) / 2` for orthographic).
    pub const DEPTH: usize = 0;
    /// `1/w`, for perspective-correct interpolation (1 in affine mode).
    pub const Q: usize = 1;
    /// `u/w` (or `u` in affine mode).
    pub const S: usize = 2;
    /// `v/w` (or `v` in affine mode).
    pub const T: usize = 3;
    /// Red, green, blue, alpha divided by `w` (or plain in affine mode).
    pub const RGBA: usize = 4;
}

/// A projected vertex: snapped screen position and the attributes interpolated across the polygon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenVertex {
    /// Screen x (pixels, right).
    pub x: Fx28_4,
    /// Screen y (pixels, down).
    pub y: Fx28_4,
    /// Interpolated attributes, see [`slot`].
    pub attrs: [f32; ATTRS],
}

/// Twice the signed area of a screen polygon in raw fixed-point units; positive when the vertex order
/// runs clockwise on screen (y down), which is glTF's back face.
#[must_use]
pub fn signed_area2(v: &[ScreenVertex]) -> i64 {
    // Each vertex with the next, the last with the first (no `% n`, which would be a division per vertex).
    let next = v.iter().skip(1).chain(v.first());
    v.iter().zip(next).map(|(p, q)| cross((p.x, p.y), (q.x, q.y))).sum()
}

/// Which way a polygon's corners run on screen (y down): the sign of its [`signed_area2`].
///
/// Set-up knows it (it culls back faces by it) and stores it with the polygon, so the fill does not sum the
/// area again in every band the polygon crosses: on the mountain's frames that sum was 2% of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Winding {
    /// Clockwise on screen (positive area): the forward chain from the top vertex runs down the right side.
    Clockwise,
    /// Counter-clockwise on screen (negative area).
    CounterClockwise,
}

impl Winding {
    /// The winding of a polygon of signed area `area` ([`signed_area2`]); `None` when it has no area.
    #[inline(always)]
    #[must_use]
    pub fn of_area(area: i64) -> Option<Self> {
        match area.signum() {
            1 => Some(Self::Clockwise),
            -1 => Some(Self::CounterClockwise),
            _ => None,
        }
    }

    /// The winding of polygon `v`; `None` when it has no area.
    #[inline]
    #[must_use]
    pub fn of(v: &[ScreenVertex]) -> Option<Self> {
        Self::of_area(signed_area2(v))
    }
}

/// [`signed_area2`] of a triangle given by its corners' positions, for set-up that has them without
/// building screen vertices.
#[inline(always)]
#[must_use]
pub(crate) fn triangle_area2([a, b, c]: [(Fx28_4, Fx28_4); 3]) -> i64 {
    cross(a, b) + cross(b, c) + cross(c, a)
}

/// The cross product of two corners' positions in raw fixed-point units: one term of the area.
#[inline(always)]
pub(crate) fn cross(p: (Fx28_4, Fx28_4), q: (Fx28_4, Fx28_4)) -> i64 {
    i64::from(p.0.0) * i64::from(q.1.0) - i64::from(q.0.0) * i64::from(p.1.0)
}
