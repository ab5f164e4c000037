//! Flat 2D triangles with premultiplied-alpha blending and a clip rectangle: how the UI (egui's meshes) is
//! drawn, through the same scanline fill as the 3D scene rather than a second renderer.
//!
//! Positions are in pixels (y down, pixel centres at `i + 0.5`), snapped to [`Fx28_4`] like everything
//! else, so UI triangles sharing an edge neither overlap nor leave gaps: a translucent panel made of two
//! triangles is blended exactly once per pixel. Colours are premultiplied RGBA, as egui gives them; the
//! texel (also premultiplied) is multiplied by the vertex colour, then `dst = src + dst * (1 - src_alpha)`.
//! Texture coordinates are interpolated linearly (there is no perspective in 2D) and sampled bilinearly.

use crate::render::core::fixed::Fx28_4;
use crate::render::core::texture::{Sampler, Texture, Wrap, blend_footprint};
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
            let Some(pixels) = frame.get_mut(row + x0..row + (span.x1.max(0) as usize).max(x0)) else { return };
            written += pixels.len() as u64;
            let at = |i: usize, x: usize| span.a0[i] + (x - span.x0 as usize) as f32 * span.da[i];
            let colour = |x: usize| {
                let r = slot::RGBA;
                [at(r, x), at(r + 1, x), at(r + 2, x), at(r + 3, x)]
            };
            // A span of one colour and one texel (a panel: egui maps a whole shape to its white texel)
            // computes its colour once: every pixel would compute the same from the same values.
            let flat_colour = (slot::RGBA..slot::RGBA + 4).all(|i| span.da[i] == 0.0);
            let one_texel = texture.is_none() || span.da[slot::S] == 0.0 && span.da[slot::T] == 0.0;
            if flat_colour && one_texel {
                let t = texture.map_or([1.0; 4], |t| t.sample_bilinear(at(slot::S, x0), at(slot::T, x0), clamp));
                let src = tinted(t, colour(x0));
                // Opaque: the destination is multiplied by 0, so every pixel gets the same colour.
                let opaque = src[3] >= 1.0;
                let fill = blend(0, src);
                for p in pixels {
                    *p = if opaque { fill } else { blend(*p, src) };
                }
                return;
            }
            for (x, p) in (x0..).zip(pixels) {
                let t = match texture {
                    Some(t) => {
                        let (texels, weights) = t.bilinear_footprint(at(slot::S, x), at(slot::T, x), clamp);
                        // Four clear texels (around a glyph) blend to a clear source, which leaves the
                        // pixel as it is.
                        if texels == [0; 4] {
                            continue;
                        }
                        blend_footprint(texels, weights)
                    }
                    None => [1.0; 4],
                };
                *p = blend(*p, tinted(t, colour(x)));
            }
        });
    }
    written
}

/// A texel (premultiplied RGBA in `0..=1`) times a vertex colour (the same): the source a pixel blends.
#[inline(always)]
fn tinted(t: [f32; 4], c: [f32; 4]) -> [f32; 4] {
    [t[0] * c[0], t[1] * c[1], t[2] * c[2], t[3] * c[3]]
}

/// Pixel `d` (`0x00RRGGBB`) under the premultiplied source `src`: `src + d * (1 - src alpha)` per channel,
/// rounded to the nearest of 256 levels.
///
/// With a clear source (all zero) this gives `d` back: `d / 255 * 255` is within a few units of the last
/// place of `d`, far from the half that rounding adds.
#[inline(always)]
fn blend(d: u32, src: [f32; 4]) -> u32 {
    let keep = 1.0 - src[3].clamp(0.0, 1.0);
    let ch = |shift: u32, s: f32| {
        let dst = ((d >> shift) & 0xff) as f32 / 255.0;
        ((s + dst * keep) * 255.0 + 0.5).clamp(0.0, 255.0) as u32
    };
    (ch(16, src[0]) << 16) | (ch(8, src[1]) << 8) | ch(0, src[2])
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

    /// The per-pixel rule the fast paths must match, written out on its own: every pixel of every span
    /// inside the clip's columns `cols` sampled, tinted and blended.
    fn every_pixel(
        frame: &mut [u32],
        w: usize,
        (verts, indices): (&[OverlayVertex], &[u32]),
        tex: Option<&Texture>,
        (rows, cols): ((i32, i32), (usize, usize)),
    ) {
        let clamp = Sampler { wrap_s: Wrap::ClampToEdge, wrap_t: Wrap::ClampToEdge };
        for tri in indices.chunks_exact(3) {
            let v: Vec<ScreenVertex> = tri.iter().filter_map(|&i| to_screen(&verts[i as usize])).collect();
            fill_spans(&v, rows, cols.1 as i32, |span| {
                for x in (span.x0 as usize).max(cols.0)..span.x1 as usize {
                    let at = |i: usize| span.a0[i] + (x - span.x0 as usize) as f32 * span.da[i];
                    let t = tex.map_or([1.0; 4], |t| t.sample_bilinear(at(slot::S), at(slot::T), clamp));
                    let r = slot::RGBA;
                    let src = [t[0] * at(r), t[1] * at(r + 1), t[2] * at(r + 2), t[3] * at(r + 3)];
                    let keep = 1.0 - src[3].clamp(0.0, 1.0);
                    let p = &mut frame[span.y as usize * w + x];
                    let d = *p;
                    let ch = |shift: u32, s: f32| {
                        let dst = ((d >> shift) & 0xff) as f32 / 255.0;
                        ((s + dst * keep) * 255.0 + 0.5).clamp(0.0, 255.0) as u32
                    };
                    *p = (ch(16, src[0]) << 16) | (ch(8, src[1]) << 8) | ch(0, src[2]);
                }
            });
        }
    }

    #[test]
    fn panels_and_glyphs_are_drawn_as_every_pixel_blended_on_its_own_would_be() {
        use crate::render::core::test_rng::Lcg;
        let mut rng = Lcg(29);
        // A glyph atlas: mostly clear, some opaque and some translucent (premultiplied) texels; its first
        // row holds one of each, which the panels take.
        let translucent = |a: u32| (a << 24) | ((a / 2) << 16) | ((a / 3) << 8) | (a / 4);
        let mut texels: Vec<u32> = (0..32 * 32)
            .map(|_| match rng.below(4) {
                0 | 1 => 0,
                2 => 0xffff_ffff,
                _ => translucent(rng.below(256)),
            })
            .collect();
        texels[..3].copy_from_slice(&[0xffff_ffff, translucent(100), 0]);
        let atlas = Texture::new(32, 32, texels).unwrap();
        let (w, h) = (48, 40);
        let mut filled = [0u32; 2];
        for case in 0..600 {
            let background: Vec<u32> = (0..w * h).map(|_| rng.next() & 0x00ff_ffff).collect();
            // Panels: one colour, one texel (opaque, translucent or clear); glyphs: texels across, one
            // colour; gradients: colours across.
            let kind = case % 3;
            let alpha = if rng.below(2) == 0 { 255 } else { rng.below(256) as u8 };
            let colour = |rng: &mut Lcg| {
                let a = if kind == 2 { rng.below(256) as u8 } else { alpha };
                [a / 2, a, a / 3, a].map(|c| c.min(a))
            };
            let texel = (rng.below(3) as f32 + 0.5) / 32.0;
            let verts: Vec<OverlayVertex> = (0..4)
                .map(|_| OverlayVertex {
                    pos: [rng.unit() * 60.0 - 6.0, rng.unit() * 50.0 - 5.0],
                    uv: if kind == 0 { [texel, 0.5 / 32.0] } else { [rng.unit(), rng.unit()] },
                    color: if kind == 1 { [200, 100, 50, 255] } else { colour(&mut rng) },
                })
                .collect();
            let indices = [0, 1, 2, 0, 2, 3];
            // Half the cases clipped to a rectangle inside the frame, whose left edge cuts spans.
            let (x0, y0) = if case % 2 == 0 { (0, 0) } else { (rng.range(1, 20) as usize, rng.range(1, 15)) };
            let (x1, y1) = if case % 2 == 0 { (w, h as i32) } else { (rng.range(25, 48) as usize, rng.range(20, 40)) };
            let clip = [x0 as f32, y0 as f32, x1 as f32, y1 as f32];
            for tex in [Some(&atlas), None] {
                let mut want = background.clone();
                every_pixel(&mut want, w, (&verts, &indices), tex, ((y0, y1), (x0, x1)));
                let mut got = background.clone();
                draw_triangles(&mut got, w, h, &verts, &indices, tex, clip);
                assert!(got == want, "case {case}, textured {}", tex.is_some());
                if kind == 0 && got != background {
                    filled[usize::from(tex.is_some())] += 1;
                }
            }
        }
        // Panels were drawn both with and without the atlas.
        assert!(filled.iter().all(|&n| n > 20), "{filled:?}");
    }
}
