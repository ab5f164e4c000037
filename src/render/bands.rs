//! The fill stage across threads: the frame is cut into horizontal bands, and every band walks the same
//! ordered polygon list drawing only its own rows. Because edge positions are exact integers and attributes
//! are evaluated per row from the polygon's vertices, a row's pixels do not depend on which band drew it.

use super::DrawList;
use super::RenderOptions;
use super::pipeline::DrawPolygon;
use super::scanline::{ScreenVertex, fill_spans};
use super::span::{Row, Shading, SpanCounts, Visibility, draw_span};

/// The rows of one band and their buffers.
pub(super) struct Band<'a> {
    y0: usize,
    rows: usize,
    color: &'a mut [u32],
    depth: &'a mut [f32],
    coverage: &'a mut [u64],
}

pub(super) fn split_bands<'a>(
    mut color: &'a mut [u32],
    mut depth: &'a mut [f32],
    mut coverage: &'a mut [u64],
    width: usize,
    words: usize,
    rows_per_band: usize,
) -> Vec<Band<'a>> {
    let height = color.len() / width;
    let mut bands = Vec::new();
    let mut y0 = 0;
    while y0 < height {
        let rows = rows_per_band.min(height - y0);
        let (c, rest) = std::mem::take(&mut color).split_at_mut(rows * width);
        color = rest;
        let (d, rest) = if depth.is_empty() {
            (&mut [][..], &mut [][..])
        } else {
            std::mem::take(&mut depth).split_at_mut(rows * width)
        };
        depth = rest;
        let (v, rest) = if coverage.is_empty() {
            (&mut [][..], &mut [][..])
        } else {
            std::mem::take(&mut coverage).split_at_mut(rows * words)
        };
        coverage = rest;
        bands.push(Band { y0, rows, color: c, depth: d, coverage: v });
        y0 += rows;
    }
    bands
}

/// Read-only state shared by the fill workers.
pub(super) struct FillContext<'a> {
    pub(super) polys: &'a [DrawPolygon],
    pub(super) screen: &'a [ScreenVertex],
    pub(super) order: &'a [u32],
    pub(super) list: &'a DrawList<'a>,
    pub(super) options: &'a RenderOptions,
    pub(super) visibility: Visibility,
    pub(super) width: usize,
    pub(super) words: usize,
}

impl FillContext<'_> {
    pub(super) fn fill_band(&self, band: Band<'_>) -> SpanCounts {
        let Band { y0, rows, color, depth, coverage } = band;
        let mut total = SpanCounts::default();
        let (w, words) = (self.width, self.words);
        for &pi in self.order {
            let p = &self.polys[pi as usize];
            let verts = &self.screen[p.first as usize..(p.first + p.count) as usize];
            let shading = Shading {
                texture: p.texture.and_then(|t| self.list.textures.get(t as usize)),
                sampler: p.sampler,
                filter: self.options.filter,
                mode: self.options.texture_mode,
                alpha_cutoff: p.alpha_cutoff,
                constant_color: p.constant_color,
                visibility: self.visibility,
                screen_door: p.screen_door,
            };
            let band_rows = (y0 as i32, (y0 + rows) as i32);
            fill_spans(verts, band_rows, w as i32, |span| {
                let r = span.y as usize - y0;
                let mut row = Row {
                    color: &mut color[r * w..(r + 1) * w],
                    depth: if depth.is_empty() { &mut [] } else { &mut depth[r * w..(r + 1) * w] },
                    coverage: if coverage.is_empty() { &mut [] } else { &mut coverage[r * words..(r + 1) * words] },
                };
                let c = draw_span(span, &shading, &mut row);
                total.shaded += c.shaded;
                total.written += c.written;
                total.rejected += c.rejected;
            });
        }
        total
    }
}
