//! The depth bias of decals: a polygon moved towards the viewer for the depth test, as GPUs' polygon offset
//! moves it.

use crate::render::core::mesh::DEPTH_BIAS_STEP;
use crate::render::core::vertex::{ScreenVertex, slot};

/// Moves a decal's depth towards the viewer for the depth test by `steps` times (one pixel of the
/// polygon's steepest depth slope plus [`DEPTH_BIAS_STEP`] of its nearest depth), as GPUs' polygon offset
/// does: the slope term covers the depth error of snapping vertices to 1/16 pixel, which at a grazing angle
/// exceeds any constant offset; the constant covers surfaces seen face on. A constant added to `1/w` keeps
/// it affine in screen space, so interpolation stays exact.
pub(crate) fn slope_scaled_bias(verts: &mut [ScreenVertex], steps: u8) {
    let d = |v: &ScreenVertex| (v.x.to_f32(), v.y.to_f32(), v.attrs[slot::DEPTH]);
    let mut slope = 0.0f32;
    let mut nearest = 0.0f32;
    if let Some(a) = verts.first().map(d) {
        for i in 1..verts.len().saturating_sub(1) {
            let (b, c) = (d(&verts[i]), d(&verts[i + 1]));
            let (e1, e2) = ((b.0 - a.0, b.1 - a.1, b.2 - a.2), (c.0 - a.0, c.1 - a.1, c.2 - a.2));
            let det = e1.0 * e2.1 - e2.0 * e1.1;
            if det.abs() > 1e-6 {
                let gx = (e1.2 * e2.1 - e2.2 * e1.1) / det;
                let gy = (e2.2 * e1.0 - e1.2 * e2.0) / det;
                slope = gx.abs().max(gy.abs());
                break;
            }
        }
    }
    for v in verts.iter() {
        nearest = nearest.max(v.attrs[slot::DEPTH].abs());
    }
    let offset = f32::from(steps) * (slope + nearest * DEPTH_BIAS_STEP);
    if offset.is_finite() {
        for v in verts.iter_mut() {
            v.attrs[slot::DEPTH] += offset;
        }
    }
}
