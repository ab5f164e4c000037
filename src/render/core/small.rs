//! The small triangle record: a triangle of at most [`MAX_SIDE`] pixels a side set up once, at polygon
//! set-up, as three integer edge functions and the plane of its attributes, for every band that draws it.
//!
//! Set-up makes it (`geometry::small_setup`, where its sub-pixel and fill rules are written) and the fill
//! draws it (`fill::small`).

use super::fixed::Fx28_4;

/// Largest bounding box side, in pixels (rows or columns whose centres it may cover), taken by this path.
pub const MAX_SIDE: i32 = 16;

/// Columns of a box drawn four lanes at a time by
/// [`fill_flat_narrow`](crate::render::fill::small::fill_flat_narrow).
pub const NARROW: usize = 4;

/// The frame a small triangle is set up for: its width; how far (raw [`Fx28_4`] units) a row's samples may
/// lie right or left of the pixel centres (0, or [`ROW_REACH`] in a frame of four rows a pixel, whose rows
/// sample shifted columns), which widens the triangle's box by as much each way; and how many rows its box
/// may have ([`MAX_SIDE`], or four times as many in a frame of four rows a pixel: the same height in the
/// picture's pixels, each a row of the box's edge-function masks as in any frame).
///
/// Every edge-function value stays within `i32` for these boxes: at most 16 columns (and the reach) by 64
/// rows of 16 raw units, so each of its two products is below `2^18`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct SmallFrame {
    /// The frame's width in pixels.
    pub(crate) width: i32,
    /// How far a row's samples may lie from the centres, raw units.
    pub(crate) reach: i32,
    /// The most rows a box may have.
    pub(crate) rows: i32,
}

impl SmallFrame {
    /// A frame `width` pixels wide whose rows sample the pixel centres.
    #[must_use]
    pub(crate) fn plain(width: i32) -> Self {
        Self { width, reach: 0, rows: MAX_SIDE }
    }

    /// A frame `width` pixels wide drawn four rows a pixel (the rotated grid).
    #[must_use]
    pub(crate) fn tall(width: i32) -> Self {
        Self { width, reach: ROW_REACH, rows: 4 * MAX_SIDE }
    }
}

/// The reach of a frame of four rows a pixel: the largest of
/// [`ROW_SHIFTS`](super::samples::ROW_SHIFTS) in magnitude.
pub(crate) const ROW_REACH: i32 = 6;

const _: () = {
    let s = super::samples::ROW_SHIFTS;
    let mut k = 0;
    while k < 4 {
        assert!(s[k] <= ROW_REACH && -s[k] <= ROW_REACH);
        k += 1;
    }
};

/// One edge function, normalised so that a pixel centre is inside when its value is positive. In a
/// bounding box of at most [`MAX_SIDE`] pixels every value is below `2^19` in magnitude, so `i32` holds it.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub(crate) struct EdgeFn {
    /// Value at the first pixel centre of the box on the current row.
    pub(crate) at_row: i32,
    /// Change per pixel to the right.
    pub(crate) step_x: i32,
    /// Change per row down.
    pub(crate) step_y: i32,
}

/// A corner of a small triangle: its snapped position and the four attributes this path interpolates
/// (depth, `1/w`, `s/w`, `t/w`: the first four of a [`ScreenVertex`](super::vertex::ScreenVertex)).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corner {
    /// Screen position.
    pub(crate) x: Fx28_4,
    pub(crate) y: Fx28_4,
    /// Depth, `1/w`, `s/w`, `t/w`.
    pub(crate) attrs: [f32; 4],
}

/// A small triangle set up once, at polygon set-up, for every band that draws it.
///
/// Polygon set-up has the corners in cache and has just computed the area; setting the triangle up there
/// (rather than in each band's fill, from the corners read back) also lets this one record stand in for
/// its three 40-byte screen vertices.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub(crate) struct SmallTriangle {
    /// The edge functions at the centre of pixel `(x_start, rows.0)`.
    pub(crate) edges: [EdgeFn; 3],
    /// First column of the box (clipped to the frame, so below 2^20) in the low 24 bits, and how many
    /// columns it has there (at most [`MAX_SIDE`]) in the high 8: packed so that the record is 64 bytes.
    pub(crate) x_columns: u32,
    /// Rows of the box (not clipped to a band).
    pub(crate) rows: [i32; 2],
    /// The first vertex's y, in pixels.
    pub(crate) y0: f32,
    /// Depth at the centre of column `x_start` on the line through the first vertex's y, and its change per
    /// pixel and per row.
    pub(crate) depth: [f32; 3],
}

// Set-up writes one record per small triangle and the fill reads it back, so its size is memory traffic
// paid twice per triangle: a flat triangle's record is one cache line, and the texture planes of a
// textured one live beside it (`TexPlanes`).
const _: () = assert!(size_of::<SmallTriangle>() == 64);

// The eight-lane set-up (`geometry::small_setup_avx2`) writes records as words in field order (plain old
// data, so two vectors cast to one): the edges'
// nine, the packed columns, the rows, the first vertex's y and the depth plane; planes as nine words.
const _: () = {
    use std::mem::offset_of;
    assert!(size_of::<EdgeFn>() == 12 && offset_of!(EdgeFn, step_x) == 4 && offset_of!(EdgeFn, step_y) == 8);
    assert!(offset_of!(SmallTriangle, x_columns) == 36 && offset_of!(SmallTriangle, rows) == 40);
    assert!(offset_of!(SmallTriangle, y0) == 48 && offset_of!(SmallTriangle, depth) == 52);
    assert!(size_of::<TexPlanes>() == 36 && offset_of!(TexPlanes, dadx) == 12 && offset_of!(TexPlanes, dady) == 24);
};

/// The planes of a textured small triangle's `1/w`, `s/w` and `t/w` (at the centre of column `x_start` on
/// the line through the first vertex's y, and their change per pixel and per row), kept beside its
/// [`SmallTriangle`]: a flat colour needs only the depth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub(crate) struct TexPlanes {
    pub(crate) a0: [f32; 3],
    pub(crate) dadx: [f32; 3],
    pub(crate) dady: [f32; 3],
}

impl TexPlanes {
    /// The planes of a flat triangle (all zero).
    pub(crate) const NONE: Self = Self { a0: [0.0; 3], dadx: [0.0; 3], dady: [0.0; 3] };
}

impl SmallTriangle {
    /// First column of the box.
    #[inline(always)]
    pub(crate) fn x_start(&self) -> usize {
        (self.x_columns & 0x00ff_ffff) as usize
    }

    /// How many columns the box has in the frame.
    #[inline(always)]
    pub(crate) fn columns(&self) -> u32 {
        self.x_columns >> 24
    }

    /// Bits of the box's columns.
    #[inline(always)]
    pub(crate) fn column_mask(&self) -> u32 {
        ((1u64 << self.columns()) - 1) as u32
    }

    /// The rows whose centres the triangle may cover, `rows().0..rows().1`.
    #[inline(always)]
    pub(crate) fn rows(&self) -> (i32, i32) {
        (self.rows[0], self.rows[1])
    }
}
