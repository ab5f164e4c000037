//! Flat 2D triangles with premultiplied-alpha blending and a clip rectangle: how the UI (egui's meshes) is
//! drawn, through the same scanline fill as the 3D scene rather than a second renderer.
//!
//! Positions are in pixels (y down, pixel centres at `i + 0.5`), snapped to [`Fx28_4`] like everything
//! else, so UI triangles sharing an edge neither overlap nor leave gaps: a translucent panel made of two
//! triangles is blended exactly once per pixel. Colours are premultiplied RGBA, as egui gives them; the
//! texel (also premultiplied) is multiplied by the vertex colour, then `dst = src + dst * (1 - src_alpha)`.
//! Texture coordinates are interpolated linearly (there is no perspective in 2D) and sampled bilinearly.

use crate::render::core::fixed::Fx28_4;
use crate::render::core::texture::{Sampler, Texture, Wrap};
use crate::render::core::vertex::{ATTRS, ScreenVertex, slot};
use crate::render::fill::scanline::fill_spans;

/// One UI vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayVertex {
    /// Position in pixels.
    pub pos: [f32; 2],
    /// Texture coordinate (0..1 across the texture).
    pub uv: [f32; 2],
    /// Premultiplied RGBA colour.
    pub color: [u8; 4],
}

/// A clip rectangle in pixels: `[x0, y0, x1, y1]`, pixels whose centres fall inside are drawn.
pub type ClipRect = [f32; 4];

fn to_screen(v: &OverlayVertex) -> Option<ScreenVertex> {
    let (x, y) = (Fx28_4::from_f32(v.pos[0])?, Fx28_4::from_f32(v.pos[1])?);
    let mut attrs = [0.0; ATTRS];
    attrs[slot::Q] = 1.0;
    attrs[slot::S] = v.uv[0];
    attrs[slot::T] = v.uv[1];
    for c in 0..4 {
        attrs[slot::RGBA + c] = f32::from(v.color[c]) / 255.0;
    }
    Some(ScreenVertex { x, y, attrs })
}

/// Draws indexed triangles into `frame` (`width * height` pixels `0x00RRGGBB`), blended, inside `clip`;
/// returns the pixels written. Triangles with a bad index or a non-finite position are skipped.
pub fn draw_triangles(
    frame: &mut [u32],
    width: usize,
    height: usize,
    vertices: &[OverlayVertex],
    indices: &[u32],
    texture: Option<&Texture>,
    clip: ClipRect,
) -> u64 {
    if frame.len() < width.saturating_mul(height) || width == 0 || height == 0 {
        return 0;
    }
    // Clip rows and columns: pixel centres inside the rectangle, within the frame.
    let lo = |v: f32, n: usize| if v.is_finite() { ((v - 0.5).ceil().max(0.0) as usize).min(n) } else { 0 };
    let (cx0, cy0) = (lo(clip[0], width), lo(clip[1], height));
    let (cx1, cy1) = (lo(clip[2], width), lo(clip[3], height));
    if cx0 >= cx1 || cy0 >= cy1 {
        return 0;
    }
    let clamp = Sampler { wrap_s: Wrap::ClampToEdge, wrap_t: Wrap::ClampToEdge };
    let mut written = 0;
    for tri in indices.chunks_exact(3) {
        let get = |i: u32| vertices.get(i as usize).and_then(to_screen);
        let (Some(a), Some(b), Some(c)) = (get(tri[0]), get(tri[1]), get(tri[2])) else {
            continue;
        };
        fill_spans(&[a, b, c], (cy0 as i32, cy1 as i32), cx1 as i32, |span| {
            let x0 = (span.x0 as usize).max(cx0);
            let row = span.y as usize * width;
            for x in x0..span.x1 as usize {
                let k = (x - span.x0 as usize) as f32;
                let at = |i: usize| span.a0[i] + k * span.da[i];
                let t = match texture {
                    Some(t) => t.sample_bilinear(at(slot::S), at(slot::T), clamp),
                    None => [1.0; 4],
                };
                let r = slot::RGBA;
                let src = [t[0] * at(r), t[1] * at(r + 1), t[2] * at(r + 2), t[3] * at(r + 3)];
                let keep = 1.0 - src[3].clamp(0.0, 1.0);
                let d = frame[row + x];
                let ch = |shift: u32, s: f32| {
                    let dst = ((d >> shift) & 0xff) as f32 / 255.0;
                    ((s + dst * keep) * 255.0 + 0.5).clamp(0.0, 255.0) as u32
                };
                frame[row + x] = (ch(16, src[0]) << 16) | (ch(8, src[1]) << 8) | ch(0, src[2]);
                written += 1;
            }
        });
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, color: [u8; 4]) -> OverlayVertex {
        OverlayVertex { pos: [x, y], uv: [0.0, 0.0], color }
    }

    #[test]
    fn translucent_quad_blends_once_per_pixel_inside_the_clip() {
        let (w, h) = (16, 12);
        let mut frame = vec![0x0000_00ffu32; w * h];
        // Half-transparent white (premultiplied: 128,128,128,128) over blue, as two triangles.
        let c = [128, 128, 128, 128];
        let verts = [v(2.0, 2.0, c), v(14.0, 2.0, c), v(14.0, 10.0, c), v(2.0, 10.0, c)];
        let n = draw_triangles(&mut frame, w, h, &verts, &[0, 1, 2, 0, 2, 3], None, [0.0, 0.0, 8.0, 12.0]);
        // Clip keeps columns 0..8: rows 2..10, columns 2..8.
        assert_eq!(n, 8 * 6);
        let blended = frame[5 * w + 4];
        assert_eq!(blended, (128 << 16) | (128 << 8) | (128 + 127 * 255 / 255));
        assert_eq!(frame[5 * w + 10], 0xff, "outside the clip rectangle");
        assert_eq!(frame[0], 0xff, "outside the quad");
        // Every covered pixel got the same colour: blended exactly once, none twice on the diagonal.
        assert!((2..10).all(|y| (2..8).all(|x| frame[y * w + x] == blended)));
    }

    #[test]
    fn textured_and_hostile_input() {
        let tex = Texture::new(2, 1, vec![0xffff_ffff, 0x0000_0000]).unwrap();
        let mut frame = vec![0u32; 8 * 8];
        let q = |x: f32, y: f32, u: f32| OverlayVertex { pos: [x, y], uv: [u, 0.5], color: [255, 0, 0, 255] };
        let verts = [q(0.0, 0.0, 0.0), q(8.0, 0.0, 1.0), q(8.0, 8.0, 1.0), q(0.0, 8.0, 0.0)];
        draw_triangles(&mut frame, 8, 8, &verts, &[0, 1, 2, 0, 2, 3], Some(&tex), [0.0, 0.0, 8.0, 8.0]);
        assert_eq!(frame[4 * 8], 0xff0000, "left: opaque white texel tinted red");
        assert_eq!(frame[4 * 8 + 7], 0, "right: transparent texel leaves the frame");
        let bad = [v(f32::NAN, 0.0, [255; 4]), v(1e30, 1.0, [255; 4]), v(0.0, 5.0, [255; 4])];
        assert_eq!(draw_triangles(&mut frame, 8, 8, &bad, &[0, 1, 2, 0, 1, 7], None, [0.0, 0.0, 8.0, 8.0]), 0);
        assert_eq!(draw_triangles(&mut [], 0, 0, &verts, &[0, 1, 2], None, [0.0, 0.0, 8.0, 8.0]), 0);
    }
}
