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
    /// Its rows of the frame (empty for a resolved frame's band, drawn into the thread's own rows).
    pub(crate) color: &'a mut [u32],
    /// Its rows of the picture, for a frame drawn larger than the picture ([`Resolve`]).
    pub(crate) out: Option<&'a mut [u32]>,
}

/// A filter from rows of a big frame into their rows of the picture (the big rows, the picture's rows, the
/// picture's width).
pub(crate) type RowFilter = fn(&[u32], &mut [u32], usize);

/// How rows of the picture are spread over their rows of a big frame before drawing over them (the
/// picture's rows, its width, the big rows).
pub(crate) type RowSpread = fn(&[u32], usize, &mut [u32]);

/// How a frame drawn larger than the picture (2x2 supersampling, the rotated grid) comes back to it. The
/// big frame is never whole: each band is drawn into the drawing thread's own rows, which stay in its
/// core's cache, and filtered into its rows of the picture as soon as it is drawn, instead of a big frame
/// (14.7 MB at 1280x720 for the rotated grid) written to memory and read back after the last band.
pub(crate) struct Resolve<'a> {
    /// The picture.
    pub(crate) out: &'a mut [u32],
    /// Rows of the big frame for each row of the picture (bands hold whole groups of them).
    pub(crate) rows: usize,
    /// What a band does with its rows of the picture.
    pub(crate) band: BandResolve,
}

/// What a band of a resolved frame does with its rows of the picture: spread them over its rows first, when
/// the frame is drawn over what is there, and filter its rows back into them once drawn.
#[derive(Clone, Copy)]
pub(crate) struct BandResolve {
    /// The filter.
    pub(crate) run: RowFilter,
    /// The spreading, when the options draw no background.
    pub(crate) spread: Option<RowSpread>,
    /// The picture's width.
    pub(crate) width: usize,
}

/// Cuts a frame `height` rows high into bands of `rows_per_band` rows (the last may be shorter), each with
/// its rows of `color` (none for a resolved frame, whose bands draw into rows of their own) and its rows
/// of the picture `out` when the frame is resolved into one (`rows_per_band` then a multiple of `group`,
/// the big frame's rows for each of the picture's).
pub(crate) fn split_bands<'a>(
    mut color: &'a mut [u32],
    (width, height): (usize, usize),
    rows_per_band: usize,
    out: Option<&'a mut [u32]>,
    (out_width, group): (usize, usize),
) -> Vec<Band<'a>> {
    let mut out = out;
    let mut bands = Vec::new();
    let mut y0 = 0;
    while y0 < height {
        let rows = rows_per_band.max(1).min(height - y0);
        let take = (rows * width).min(color.len());
        let (c, rest) = std::mem::take(&mut color).split_at_mut(take);
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
