//! 2x2 supersampling's two passes around the drawing at twice the size: each pixel of the frame becomes its
//! four when the frame is drawn over what is there, and each 2x2 block of the big frame becomes one pixel, the
//! rounded mean of its four colours channel by channel (`(sum + 2) / 4`). And the rotated grid's, around its
//! frame of four rows a pixel (whose rows the fill samples at shifted columns, `core::samples::ROW_SHIFTS`):
//! each pixel becomes a column of four, and each column of four one pixel, by the same rounding.
//!
//! The mean adds red and blue in one word (each sum of four fits in ten bits, sixteen bits apart) and green
//! in another, so a pixel costs a few integer operations. The fill resolves each band as soon as it is drawn,
//! on the thread that drew it, while its rows are still in the core's cache (`core::band::Resolve`); each
//! output pixel depends only on its own block, so the frame is the same for every thread count.

/// Copies each pixel of `frame` (`width` pixels a row) into its 2x2 block of `big`, which is twice the width
/// and height.
pub(crate) fn expand(frame: &[u32], width: usize, big: &mut [u32]) {
    let bw = 2 * width;
    for (row, pair) in frame.chunks_exact(width).zip(big.chunks_exact_mut(2 * bw)) {
        let (top, bottom) = pair.split_at_mut(bw);
        for (two, &c) in top.chunks_exact_mut(2).zip(row) {
            two.fill(c);
        }
        bottom.copy_from_slice(top);
    }
}

/// The rounded mean, channel by channel, of four `0x00RRGGBB` colours (the top byte is ignored).
#[inline]
fn mean4(a: u32, b: u32, c: u32, d: u32) -> u32 {
    const RB: u32 = 0x00ff_00ff;
    const G: u32 = 0x0000_ff00;
    let rb = (a & RB) + (b & RB) + (c & RB) + (d & RB) + 0x0002_0002;
    let g = (a & G) + (b & G) + (c & G) + (d & G) + 0x0000_0200;
    ((rb >> 2) & RB) | ((g >> 2) & G)
}

/// Box-filters rows of `big` (twice the width, two rows for each of `out`'s) into `out` (`width` a row): a
/// band of the big frame into its rows of the picture, each output pixel from its own 2x2 block only.
pub(crate) fn box_filter(big: &[u32], out: &mut [u32], width: usize) {
    let bw = 2 * width;
    for (row, pair) in out.chunks_exact_mut(width).zip(big.chunks_exact(2 * bw)) {
        let (top, bottom) = pair.split_at(bw);
        for ((o, t), b) in row.iter_mut().zip(top.chunks_exact(2)).zip(bottom.chunks_exact(2)) {
            *o = mean4(t[0], t[1], b[0], b[1]);
        }
    }
}

/// Copies each row of `frame` (`width` pixels a row) into four rows of `tall`, which is four times the height.
pub(crate) fn expand_rows(frame: &[u32], width: usize, tall: &mut [u32]) {
    for (row, four) in frame.chunks_exact(width).zip(tall.chunks_exact_mut(4 * width)) {
        for copy in four.chunks_exact_mut(width) {
            copy.copy_from_slice(row);
        }
    }
}

/// Each column of four pixels of `tall` (four times `frame`'s height) as the rounded mean of the four, into
/// `frame` (`width` pixels a row): a band of the tall frame into its rows of the picture.
pub(crate) fn mean_rows(tall: &[u32], frame: &mut [u32], width: usize) {
    if width == 0 {
        return;
    }
    for (row, four) in frame.chunks_exact_mut(width).zip(tall.chunks_exact(4 * width)) {
        let (a, rest) = four.split_at(width);
        let (b, rest) = rest.split_at(width);
        let (c, d) = rest.split_at(width);
        for ((((o, &a), &b), &c), &d) in row.iter_mut().zip(a).zip(b).zip(c).zip(d) {
            *o = mean4(a, b, c, d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::test_rng::Lcg;

    /// 32 random bits.
    fn word(r: &mut Lcg) -> u32 {
        (r.next() << 1) ^ r.next()
    }

    /// The mean as it was first written: each channel on its own.
    fn mean4_per_channel(q: [u32; 4]) -> u32 {
        let ch = |shift: u32| (q.iter().map(|&c| (c >> shift) & 0xff).sum::<u32>() + 2) / 4;
        (ch(16) << 16) | (ch(8) << 8) | ch(0)
    }

    #[test]
    fn expanded_rows_come_back_and_the_mean_of_four_rows_is_each_columns_mean() {
        let (w, h) = (23, 37);
        let mut rng = Lcg(5);
        let frame: Vec<u32> = (0..w * h).map(|_| word(&mut rng) & 0x00ff_ffff).collect();
        let mut tall = vec![0u32; 4 * w * h];
        expand_rows(&frame, w, &mut tall);
        assert_eq!(tall[(4 * 5 + 3) * w + 7], frame[5 * w + 7]);
        let mut back = vec![0u32; w * h];
        mean_rows(&tall, &mut back, w);
        assert_eq!(back, frame);
        let tall: Vec<u32> = (0..4 * w * h).map(|_| word(&mut rng)).collect();
        let want: Vec<u32> = (0..w * h)
            .map(|i| {
                let (y, x) = (i / w, i % w);
                mean4_per_channel(std::array::from_fn(|k| tall[(4 * y + k) * w + x]))
            })
            .collect();
        let mut one = vec![0u32; w * h];
        mean_rows(&tall, &mut one, w);
        assert_eq!(one, want);
        // Band by band (whole groups of four rows), as the fill resolves them: the same pixels.
        let mut banded = vec![0u32; w * h];
        for (out, band) in banded.chunks_mut(5 * w).zip(tall.chunks(20 * w)) {
            mean_rows(band, out, w);
        }
        assert_eq!(banded, want);
    }

    #[test]
    fn the_packed_mean_is_the_per_channel_mean() {
        let mut rng = Lcg(7);
        let edges = [0, 1, 2, 3, 0xff, 0xfe, 0x80, 0x7f];
        for i in 0..200_000u32 {
            let q: [u32; 4] = if i < 4096 {
                // Every four of the values where rounding and carries turn, in every channel at once (and a top
                // byte set, which the mean ignores).
                std::array::from_fn(|k| {
                    let e = edges[((i >> (3 * k as u32)) & 7) as usize];
                    (e << 16) | (e << 8) | e | 0xff00_0000
                })
            } else {
                std::array::from_fn(|_| word(&mut rng))
            };
            assert_eq!(mean4(q[0], q[1], q[2], q[3]), mean4_per_channel(q), "{q:08x?}");
        }
    }

    #[test]
    fn expanded_then_filtered_is_the_frame_whole_or_band_by_band() {
        let (w, h) = (37, 41);
        let mut rng = Lcg(11);
        let frame: Vec<u32> = (0..w * h).map(|_| word(&mut rng) & 0x00ff_ffff).collect();
        let mut big = vec![0u32; 4 * w * h];
        expand(&frame, w, &mut big);
        assert_eq!(big[(2 * 5 + 1) * 2 * w + 2 * 7 + 1], frame[5 * w + 7]);
        let mut back = vec![0u32; w * h];
        box_filter(&big, &mut back, w);
        assert_eq!(back, frame);
        // A big frame of noise, filtered whole and band by band (whole pairs of rows, as the fill resolves
        // them): the same pixels.
        let big: Vec<u32> = (0..4 * w * h).map(|_| word(&mut rng)).collect();
        let (mut one, mut banded) = (vec![0u32; w * h], vec![1u32; w * h]);
        box_filter(&big, &mut one, w);
        for (out, band) in banded.chunks_mut(3 * w).zip(big.chunks(6 * 2 * w)) {
            box_filter(band, out, w);
        }
        assert_eq!(one, banded);
        let q = |x: usize, y: usize| big[y * 2 * w + x];
        assert_eq!(one[3 * w + 4], mean4_per_channel([q(8, 6), q(9, 6), q(8, 7), q(9, 7)]));
    }
}
