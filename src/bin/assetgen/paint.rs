//! Deterministic texture painting: an RGBA canvas with rectangles, discs, stripes, a 5x7 digit font,
//! box-filter downscaling, and PNG output.

use std::path::Path;

/// An 8-bit RGBA image.
#[derive(Clone, Debug)]
pub struct Canvas {
    /// Width in pixels.
    pub w: u32,
    /// Height in pixels.
    pub h: u32,
    /// RGBA bytes, rows from the top.
    pub px: Vec<u8>,
}

/// An RGBA colour.
pub type Rgba = [u8; 4];

impl Canvas {
    /// A canvas filled with `c`.
    pub fn new(w: u32, h: u32, c: Rgba) -> Self {
        Self { w, h, px: c.iter().copied().cycle().take((w * h * 4) as usize).collect() }
    }

    /// Sets one pixel (ignored outside).
    pub fn set(&mut self, x: i32, y: i32, c: Rgba) {
        if x >= 0 && y >= 0 && (x as u32) < self.w && (y as u32) < self.h {
            let i = ((y as u32 * self.w + x as u32) * 4) as usize;
            self.px[i..i + 4].copy_from_slice(&c);
        }
    }

    /// Fills a rectangle given in fractions of the canvas (`x0, y0, x1, y1` in 0..1).
    pub fn rect(&mut self, r: [f32; 4], c: Rgba) {
        let (x0, y0) = ((r[0] * self.w as f32).round() as i32, (r[1] * self.h as f32).round() as i32);
        let (x1, y1) = ((r[2] * self.w as f32).round() as i32, (r[3] * self.h as f32).round() as i32);
        for y in y0..y1 {
            for x in x0..x1 {
                self.set(x, y, c);
            }
        }
    }

    /// Fills a disc (centre and radius in fractions of the width).
    pub fn disc(&mut self, cx: f32, cy: f32, r: f32, c: Rgba) {
        let (w, h) = (self.w as f32, self.h as f32);
        for y in 0..self.h {
            for x in 0..self.w {
                let dx = (x as f32 + 0.5) / w - cx;
                let dy = ((y as f32 + 0.5) / h - cy) * h / w;
                if dx * dx + dy * dy <= r * r {
                    self.set(x as i32, y as i32, c);
                }
            }
        }
    }

    /// Draws decimal digits with a 5x7 font scaled to `height` (fraction of the canvas height), centred.
    pub fn number(&mut self, n: u32, cx: f32, cy: f32, height: f32, c: Rgba) {
        let text = n.to_string();
        let cell = (height * self.h as f32 / 7.0).max(1.0);
        let total_w = text.len() as f32 * 6.0 * cell - cell;
        let x0 = cx * self.w as f32 - total_w / 2.0;
        let y0 = cy * self.h as f32 - 3.5 * cell;
        for (k, ch) in text.bytes().enumerate() {
            let glyph = DIGITS[usize::from(ch - b'0')];
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0x10 >> col) != 0 {
                        let gx = x0 + (k as f32 * 6.0 + col as f32) * cell;
                        let gy = y0 + row as f32 * cell;
                        for yy in gy.round() as i32..(gy + cell).round() as i32 {
                            for xx in gx.round() as i32..(gx + cell).round() as i32 {
                                self.set(xx, yy, c);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Box-filters down to `w` x `h` (integer factors of the current size).
    pub fn downscale(&self, w: u32, h: u32) -> Canvas {
        let (fx, fy) = (self.w / w, self.h / h);
        let mut out = Canvas::new(w, h, [0; 4]);
        for y in 0..h {
            for x in 0..w {
                let mut acc = [0u32; 4];
                for yy in 0..fy {
                    for xx in 0..fx {
                        let i = (((y * fy + yy) * self.w + x * fx + xx) * 4) as usize;
                        for (c, a) in acc.iter_mut().enumerate() {
                            *a += u32::from(self.px[i + c]);
                        }
                    }
                }
                let n = fx * fy;
                let px = acc.map(|a| ((a + n / 2) / n) as u8);
                out.set(x as i32, y as i32, px);
            }
        }
        out
    }

    /// Writes the canvas as an RGBA PNG.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        image::save_buffer_with_format(path, &self.px, self.w, self.h, image::ColorType::Rgba8, image::ImageFormat::Png)
            .map_err(std::io::Error::other)
    }
}

/// 5x7 digits, one byte per row, bit 4 the leftmost column.
const DIGITS: [[u8; 7]; 10] = [
    [0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e],
    [0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e],
    [0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f],
    [0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e],
    [0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02],
    [0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e],
    [0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e],
    [0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
    [0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e],
    [0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c],
];
