//! The polygon record set-up hands to ordering and fill, how it is painted, and the rule that says which
//! polygons take a fast path.

use glam::Vec4;

use super::door::Door;
use super::options::{MipMode, TextureMode};
use crate::render::core::fixed::Fx28_4;
use crate::render::core::mip::LOD_STEPS;
use crate::render::core::texture::{Filter, Sampler};
use crate::render::core::vertex::{ScreenVertex, Winding};

/// A polygon (or a piece of one) ready for the fill stage.
///
/// Set-up writes one per polygon and the ordering, binning and fill stages read them back, so its size is
/// paid at every stage and the record is kept to 48 bytes: the optional parts of its paint are values with
/// flags, and ordering keys live beside the polygons ([`Batch::keys`](crate::render::core::batch::Batch::keys)),
/// only for the methods that order by them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DrawPolygon {
    /// Its first screen vertex in its batch, or for a small triangle its set-up's index there: in the batch's
    /// textured small triangles when it has a texture ([`HAS_TEXTURE`]), else in its flat ones.
    pub(crate) first: u32,
    /// How many corners it has.
    pub(crate) count: u32,
    /// The batch holding its screen vertices or small triangle (see
    /// [`Screens`](crate::render::core::batch::Screens)).
    pub(crate) batch: u32,
    /// The rows whose centres it covers, `rows.0..rows.1` (before clipping to the frame).
    pub(crate) rows: (i32, i32),
    /// The texture index when [`HAS_TEXTURE`] is set; otherwise, with [`HAS_COLOR`], the colour packed as
    /// `0x00RRGGBB` ([`pack_rgb`]), which the fill of flat small triangles takes per triangle.
    texture: u32,
    /// The alpha cutoff, when [`HAS_CUTOFF`] is set.
    cutoff: f32,
    /// The colour of every corner, when [`HAS_COLOR`] is set.
    color: [f32; 4],
    pub(crate) sampler: Sampler,
    /// [`HAS_TEXTURE`], [`HAS_CUTOFF`], [`HAS_COLOR`], [`CLOCKWISE`], [`SMALL`], and the screen door's 3 bits
    /// from [`DOOR_SHIFT`] up.
    flags: u8,
    /// Its texture's level of detail `λ` in steps of 1/[`LOD_STEPS`] when mip levels are chosen per polygon
    /// (0 otherwise): the record's last free byte, so a polygon still takes 48.
    lod: u8,
}

const _: () = assert!(size_of::<DrawPolygon>() == 48);

/// [`DrawPolygon::flags`]: it has a texture.
const HAS_TEXTURE: u8 = 1;
/// It has an alpha cutoff.
const HAS_CUTOFF: u8 = 2;
/// All its corners have one colour.
const HAS_COLOR: u8 = 4;
/// Its corners run clockwise on screen ([`Winding::Clockwise`]; set for polygons with corners only).
const CLOCKWISE: u8 = 8;
/// Where the screen door's 3 bits ([`Door::bits`]) sit in the flags.
const DOOR_SHIFT: u32 = 5;
/// It is a small triangle set up for the fast path: `first` indexes its batch's small triangles (textured or
/// flat, by [`HAS_TEXTURE`]) and it has no screen vertices.
const SMALL: u8 = 16;

/// How a polygon is painted: what [`DrawPolygon`] stores compactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct PolygonPaint {
    pub(crate) texture: Option<u32>,
    pub(crate) sampler: Sampler,
    pub(crate) alpha_cutoff: Option<f32>,
    pub(crate) constant_color: Option<[f32; 4]>,
    /// The screen door it is drawn through (see-through instances, level-of-detail fades), if any.
    pub(crate) door: Door,
    /// The polygon's `λ` in steps of 1/[`LOD_STEPS`] (mip levels chosen per polygon; else 0).
    pub(crate) lod: u8,
}

impl DrawPolygon {
    /// A polygon with corners `first..first + count` of batch `batch` (or small triangle `first` there, when
    /// `small`), covering `rows`, painted `paint`.
    #[inline]
    pub(crate) fn new(first: u32, count: u32, batch: u32, rows: (i32, i32), small: bool, paint: &PolygonPaint) -> Self {
        let packed = paint.texture.unwrap_or_else(|| paint.constant_color.map_or(0, pack_rgb));
        Self::packed(first, count, batch, rows, small, paint, packed)
    }

    /// [`Self::new`] given what it would store beside the colour: the texture index when textured, else
    /// [`pack_rgb`] of the constant colour (set-up packs eight at a time).
    #[inline(always)]
    pub(crate) fn packed(
        first: u32,
        count: u32,
        batch: u32,
        rows: (i32, i32),
        small: bool,
        paint: &PolygonPaint,
        packed: u32,
    ) -> Self {
        debug_assert_eq!(packed, paint.texture.unwrap_or_else(|| paint.constant_color.map_or(0, pack_rgb)));
        let flag = |on: bool, f: u8| if on { f } else { 0 };
        let flags = flag(paint.texture.is_some(), HAS_TEXTURE)
            | flag(paint.alpha_cutoff.is_some(), HAS_CUTOFF)
            | flag(paint.constant_color.is_some(), HAS_COLOR)
            | paint.door.bits() << DOOR_SHIFT
            | flag(small, SMALL);
        Self {
            first,
            count,
            batch,
            rows,
            texture: packed,
            cutoff: paint.alpha_cutoff.unwrap_or(0.0),
            color: paint.constant_color.unwrap_or([0.0; 4]),
            sampler: paint.sampler,
            flags,
            lod: paint.lod,
        }
    }

    /// The same polygon with its corners' winding `w` (set-up's, from the area it culled by), which the fill
    /// walks its edges by.
    #[inline(always)]
    #[must_use]
    pub(crate) fn wound(mut self, w: Winding) -> Self {
        self.flags = (self.flags & !CLOCKWISE) | if w == Winding::Clockwise { CLOCKWISE } else { 0 };
        self
    }

    /// Which way its corners run on screen, as set-up found it ([`Self::wound`]).
    #[inline(always)]
    pub(crate) fn winding(&self) -> Winding {
        if self.flags & CLOCKWISE != 0 { Winding::Clockwise } else { Winding::CounterClockwise }
    }

    /// Its texture index.
    #[inline(always)]
    pub(crate) fn texture(&self) -> Option<u32> {
        (self.flags & HAS_TEXTURE != 0).then_some(self.texture)
    }

    /// Its alpha cutoff.
    #[inline(always)]
    pub(crate) fn alpha_cutoff(&self) -> Option<f32> {
        (self.flags & HAS_CUTOFF != 0).then_some(self.cutoff)
    }

    /// The colour of all its corners, if they share one.
    #[inline(always)]
    pub(crate) fn constant_color(&self) -> Option<[f32; 4]> {
        (self.flags & HAS_COLOR != 0).then_some(self.color)
    }

    /// Its colour packed as `0x00RRGGBB`, for a polygon of one colour with no texture (0 otherwise).
    #[inline(always)]
    pub(crate) fn flat_rgb(&self) -> u32 {
        if self.flags & (HAS_TEXTURE | HAS_COLOR) == HAS_COLOR { self.texture } else { 0 }
    }

    /// Its level of detail `λ` as chosen at set-up (mip levels per polygon; else 0).
    #[inline(always)]
    pub(crate) fn lod(&self) -> f32 {
        f32::from(self.lod) / LOD_STEPS
    }

    /// The screen door it is drawn through ([`Door::NONE`] for none).
    #[inline(always)]
    pub(crate) fn door(&self) -> Door {
        Door::from_bits(self.flags >> DOOR_SHIFT)
    }

    /// Whether it is a small triangle set up for the fast path.
    #[inline(always)]
    pub(crate) fn small(&self) -> bool {
        self.flags & SMALL != 0
    }

    /// Whether `other` is painted the same (texture and its level of detail, sampler, cutoff and colour; not
    /// the screen door).
    #[inline(always)]
    pub(crate) fn paints_like(&self, other: &Self) -> bool {
        (self.texture(), self.lod, self.sampler, self.alpha_cutoff(), self.constant_color())
            == (other.texture(), other.lod, other.sampler, other.alpha_cutoff(), other.constant_color())
    }
}

/// Packs RGBA in `0..=1` into `0x00RRGGBB`, rounding to nearest; NaN becomes 0.
#[inline]
#[must_use]
pub fn pack_rgb(c: [f32; 4]) -> u32 {
    // The channels four at a time (set-up packs every flat polygon's colour, a small triangle's among them,
    // so four scalar clamps and saturating conversions would sit in its hottest loop). The vector clamp
    // sends NaN to 0, as the conversion of a NaN does.
    let v = (Vec4::from_array(c) * 255.0 + Vec4::splat(0.5)).clamp(Vec4::ZERO, Vec4::splat(255.0));
    // Truncation of values in 0..=255 without a conversion per channel: adding 2^23 rounds to the nearest
    // integer (exactly, the spacing of floats there being 1), one less where that rounded up. The channels
    // are then whole numbers below 256, so `r * 65536 + g * 256 + b` is exact in f32 (below 2^24) and one
    // conversion packs them.
    let magic = Vec4::splat(8_388_608.0);
    let rounded = (v + magic) - magic;
    let whole = rounded - Vec4::select(rounded.cmpgt(v), Vec4::ONE, Vec4::ZERO);
    (whole.x * 65_536.0 + whole.y * 256.0 + whole.z) as u32
}

/// What decides whether a polygon's spans take a fast path, known before any span is drawn: polygon set-up
/// asks it to prepare small triangles only for polygons the fill will draw that way.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FastPathRule {
    /// The texture filter of the frame.
    pub(crate) filter: Filter,
    /// The texture mode of the frame.
    pub(crate) mode: TextureMode,
    /// Where mip levels are chosen (the fast paths take every choice; small triangles one level).
    pub(crate) mip: MipMode,
}

impl FastPathRule {
    /// Whether a polygon with (or without) a texture, a constant colour and an alpha cutoff, drawn with or
    /// without the screen door, takes a fast path. The one place this is decided: the fill's span
    /// preparation picks its path by it, and set-up by it ([`small_triangles`](Self::small_triangles)) sets
    /// small triangles up for the fast fill.
    #[inline]
    pub(crate) fn applies(&self, textured: bool, constant_color: bool, alpha_cutoff: bool, screen_door: bool) -> bool {
        let perspective = self.mode == TextureMode::Perspective;
        !screen_door && constant_color && if textured { perspective } else { !alpha_cutoff }
    }

    /// Whether set-up makes such a polygon's small triangles for the fast fill: when it takes a fast path
    /// with nearest texels (or none) from one level for it. A level chosen per span or pixel needs the
    /// polygon's gradients, which a small triangle's record does not carry, and the small fill samples
    /// nearest only, so such triangles stay polygons. With [`Filter::MinBilinear`] a textured triangle
    /// also asks [`small_textured_at`](Self::small_textured_at) with its level of detail.
    #[inline]
    pub(crate) fn small_triangles(&self, textured: bool, constant: bool, cutoff: bool, screen_door: bool) -> bool {
        let one_level = matches!(self.mip, MipMode::Off | MipMode::Polygon);
        let one_nearest_level = one_level && matches!(self.filter, Filter::Nearest | Filter::MinBilinear);
        self.applies(textured, constant, cutoff, screen_door) && (!textured || one_nearest_level)
    }

    /// Whether a textured triangle whose material's small triangles take the fast fill
    /// ([`small_triangles`](Self::small_triangles)) is drawn with nearest texels at its level of detail
    /// `lod` (in steps of 1/[`LOD_STEPS`](super::mip::LOD_STEPS)), a cut-out when `cut_out`, and so is a
    /// small triangle too: always, except a minified one with [`Filter::MinBilinear`] that is no cut-out,
    /// which stays a polygon and is drawn bilinear ([`Filter::for_surface`]).
    #[inline(always)]
    pub(crate) fn small_textured_at(&self, lod: u8, cut_out: bool) -> bool {
        self.filter.for_surface(f32::from(lod), cut_out) == Filter::Nearest
    }
}

/// The rows whose centres a polygon covers: those in `[top, bottom)`, the scanline walk's rule; or, when
/// `antialiased`, every row its extent touches (a sample may lie anywhere in a row).
pub(crate) fn rows_of(v: &[ScreenVertex], antialiased: bool) -> (i32, i32) {
    let (mut top, mut bottom) = (Fx28_4(i32::MAX), Fx28_4(i32::MIN));
    for p in v {
        top = top.min(p.y);
        bottom = bottom.max(p.y);
    }
    match (top > bottom, antialiased) {
        (true, _) => (0, 0),
        (false, true) => (top.0 >> 4, ((i64::from(bottom.0) + 15) >> 4) as i32),
        (false, false) => (top.first_centre_at_or_after(), bottom.first_centre_at_or_after()),
    }
}
