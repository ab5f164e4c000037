//! The band target: how a frame is cut into horizontal bands of rows that the fill draws in parallel, and
//! which bands each polygon touches.

use super::polygon::DrawPolygon;

/// Rows per band, about: small enough that a band's colour and depth rows stay in the core's cache while it
/// is drawn and that bands balance across threads, large enough that few polygons are set up twice. The
/// band count is first rounded up to a multiple of the thread count, then the height is cut into bands of
/// equal rows, which gives that many bands when the height divides well (480 rows on 2 threads: 16 bands of
/// 30 rows, not 15 of 32, of which one thread would draw 8). The band layout never changes a pixel (a test
/// renders with 1 to 400 threads).
const BAND_ROWS: usize = 32;

/// A frame's size, the threads drawing it and the rows of each band.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct FrameLayout {
    /// Frame width in pixels.
    pub(crate) width: usize,
    /// Frame height in pixels.
    pub(crate) height: usize,
    /// Worker threads (at least 1, at most the height).
    pub(crate) threads: usize,
    /// Rows of every band but maybe the last.
    pub(crate) rows_per_band: usize,
}

impl FrameLayout {
    /// About [`BAND_ROWS`] rows a band, and (when the height divides well) a number of bands the threads
    /// share evenly.
    #[must_use]
    pub(crate) fn new(width: usize, height: usize, threads: usize) -> Self {
        let threads = threads.clamp(1, height.max(1));
        let bands = height.div_ceil(BAND_ROWS).next_multiple_of(threads).max(1);
        Self { width, height, threads, rows_per_band: height.div_ceil(bands).max(1) }
    }

    /// This layout with bands of whole groups of `rows` rows (each band of a frame resolved into a smaller
    /// picture must hold every row the picture's rows come from).
    #[must_use]
    pub(crate) fn grouped(self, rows: usize) -> Self {
        Self { rows_per_band: self.rows_per_band.next_multiple_of(rows.max(1)), ..self }
    }
}

/// The rows of one band and their colour.
pub(crate) struct Band<'a> {
    /// Its first row in the frame.
    pub(crate) y0: usize,
    /// How many rows it has.
    pub(crate) rows: usize,
    /// Its rows of the frame.
    pub(crate) color: &'a mut [u32],
    /// Where its rows are resolved to once drawn, for a frame drawn larger than the picture (see
    /// [`Resolve`]): its rows of the picture.
    pub(crate) out: Option<&'a mut [u32]>,
}

/// A filter from rows of a big frame into their rows of the picture (the big rows, the picture's rows, the
/// picture's width).
pub(crate) type RowFilter = fn(&[u32], &mut [u32], usize);

/// How a frame drawn larger than the picture (2x2 supersampling, the rotated grid) comes back to it: each
/// band, once drawn, is filtered into its rows of the picture while its rows are still in the core's cache,
/// instead of the whole big frame being read back from memory after the last band.
pub(crate) struct Resolve<'a> {
    /// The picture.
    pub(crate) out: &'a mut [u32],
    /// The picture's width.
    pub(crate) width: usize,
    /// Rows of the big frame for each row of the picture (bands hold whole groups of them).
    pub(crate) rows: usize,
    /// The filter: rows of the big frame into rows of the picture `width` a row.
    pub(crate) run: RowFilter,
}

/// Cuts the frame into bands of `rows_per_band` rows (the last may be shorter), each with its rows of the
/// picture `out` when the frame is resolved into one (`rows_per_band` then a multiple of its `rows`).
pub(crate) fn split_bands<'a>(
    mut color: &'a mut [u32],
    width: usize,
    rows_per_band: usize,
    out: Option<&'a mut [u32]>,
    (out_width, group): (usize, usize),
) -> Vec<Band<'a>> {
    let height = color.len() / width.max(1);
    let mut out = out;
    let mut bands = Vec::new();
    let mut y0 = 0;
    while y0 < height {
        let rows = rows_per_band.max(1).min(height - y0);
        let (c, rest) = std::mem::take(&mut color).split_at_mut(rows * width);
        color = rest;
        debug_assert!(out.is_none() || rows.is_multiple_of(group.max(1)), "a band holds whole groups of rows");
        let mine = out.take().map(|o| {
            let (mine, rest) = o.split_at_mut((rows / group.max(1) * out_width).min(o.len()));
            out = Some(rest);
            mine
        });
        bands.push(Band { y0, rows, color: c, out: mine });
        y0 += rows;
    }
    bands
}

/// Puts each polygon of `order` (indices into `polys`, in order) into the bin of every band of
/// `rows_per_band` rows it touches.
pub(crate) fn bin(
    polys: &[DrawPolygon],
    order: impl Iterator<Item = u32>,
    (height, rows_per_band): (usize, usize),
    bins: &mut Vec<Vec<u32>>,
) {
    let rows_per_band = rows_per_band.max(1);
    let count = height.div_ceil(rows_per_band);
    bins.resize_with(count, Vec::new);
    bins.truncate(count);
    bins.iter_mut().for_each(Vec::clear);
    for pi in order {
        let Some(p) = polys.get(pi as usize) else { continue };
        // The rows were found at set-up, where the vertices were at hand: here they would be a cache miss.
        let first = p.rows.0.max(0) as usize;
        let end = (p.rows.1.max(0) as usize).min(height);
        if first >= end {
            continue;
        }
        for b in bins.iter_mut().take((end - 1) / rows_per_band + 1).skip(first / rows_per_band) {
            b.push(pi);
        }
    }
}
