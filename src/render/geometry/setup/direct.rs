//! The direct path of small triangles: set up straight from the transformed vertices' records, without
//! building screen vertices, one triangle at a time (and the pieces the eight-lane path shares with it).

use super::{MaterialSetup, ObjectSetup, key_sum};
use crate::render::core::batch::Batch;
use crate::render::core::mesh::Material;
use crate::render::core::mip::polygon_lod;
use crate::render::core::polygon::{DrawPolygon, PolygonPaint, pack_rgb};
use crate::render::core::small::{Corner, SmallTriangle, TexPlanes};

impl ObjectSetup<'_> {
    /// Sets up a projected triangle of signed area `area` (not culled) that is a small triangle with a fast
    /// path straight from its vertices, giving exactly what [`Self::gather_inside`] and [`Self::finish`]
    /// give; `false`, with nothing written or counted, for any other polygon.
    ///
    /// The general path writes three 40-byte screen vertices, reads them back for the area, the key and
    /// the small triangle's set-up, and then drops them; this path reads the per-vertex records directly,
    /// which spares set-up that round trip through memory for every small triangle.
    #[inline]
    pub(super) fn set_up_small(
        &self,
        idx: &[u32],
        area: i64,
        material: &Material,
        m: &MaterialSetup,
        out: &mut Batch,
    ) -> bool {
        let &[i0, i1, i2] = idx else { return false };
        let ids = [i0 as usize, i1 as usize, i2 as usize];
        let v = self.vertices;
        let s = [v[ids[0]].screen_or_zero(), v[ids[1]].screen_or_zero(), v[ids[2]].screen_or_zero()];
        if !SmallTriangle::fits([(s[0].0, s[0].1), (s[1].0, s[1].1), (s[2].0, s[2].1)], self.small_frame()) {
            return false;
        }
        let Some(color) = self.flat_color(&ids, material) else { return false };
        let corners = self.corners(&ids);
        let lod = Self::small_lod(m, || corners);
        if m.texture.is_some() && !self.fast_path.small_textured_at(lod, m.alpha_cutoff.is_some()) {
            return false;
        }
        let t = match m.texture {
            None => SmallTriangle::from_corners::<1>(&corners, area, self.small_frame()),
            Some(_) => SmallTriangle::from_corners::<4>(&corners, area, self.small_frame()),
        };
        let Some(t) = t else {
            debug_assert!(false, "a triangle that fits was not set up");
            return false;
        };
        let packed = m.texture.unwrap_or_else(|| pack_rgb(color));
        self.push_small(t, &ids, (color, lod, packed), (material, m), out);
        true
    }

    /// The colour of triangle `ids` in `material` when its three corners share one, as
    /// [`Self::gather_inside`] compares them; only such a triangle has a fast path
    /// ([`MaterialSetup::small`]).
    #[inline(always)]
    pub(super) fn flat_color(&self, ids: &[usize; 3], material: &Material) -> Option<[f32; 4]> {
        // Arrays built element by element: the compiler does not inline `[T; N]::map` here.
        let mv = self.mesh.vertices();
        let verts = [&mv[ids[0]], &mv[ids[1]], &mv[ids[2]]];
        let product = |k: usize| verts[k].color * material.base_color;
        let p0 = product(0);
        let color0 = p0.to_array();
        // Equal vertex colours give equal products (as `==` compares them) unless a product is NaN (an
        // infinite channel times 0), which `gather_inside` finds unequal to itself; otherwise the products
        // are compared, as it does. (`&`, not `&&`: three compares are cheaper than the branches between
        // them.)
        let c = verts[0].color;
        let same = (verts[1].color == c) & (verts[2].color == c) & !p0.is_nan();
        let equal = same || (product(1).to_array() == color0 && product(2).to_array() == color0);
        equal.then_some(color0)
    }

    /// The corners of projected triangle `ids` as the small-triangle set-up takes them.
    #[inline(always)]
    pub(super) fn corners(&self, ids: &[usize; 3]) -> [Corner; 3] {
        let (v, mv) = (self.vertices, self.mesh.vertices());
        let corner = |k: usize| {
            let (x, y, depth, q) = v[ids[k]].screen_or_zero();
            let m = if self.perspective_attrs { q } else { 1.0 };
            Corner { x, y, attrs: [depth, m, mv[ids[k]].uv.x * m, mv[ids[k]].uv.y * m] }
        };
        [corner(0), corner(1), corner(2)]
    }

    /// The level of detail of triangle `corners` when its material's levels are chosen per polygon, else 0.
    #[inline(always)]
    pub(super) fn small_lod(m: &MaterialSetup, corners: impl FnOnce() -> [Corner; 3]) -> u8 {
        m.mip_size.map_or(0, |size| {
            let c = |k: &Corner| [k.x.to_f32(), k.y.to_f32(), k.attrs[1], k.attrs[2], k.attrs[3]];
            polygon_lod(corners().iter().map(c), size)
        })
    }

    /// Pushes small triangle `t` of corners `ids`, colour `color` and level of detail `lod`, with its draw
    /// polygon and key, and counts it drawn.
    #[inline(always)]
    pub(super) fn push_small(
        &self,
        t: (SmallTriangle, TexPlanes),
        ids: &[usize; 3],
        (color, lod, packed): ([f32; 4], u8, u32),
        (material, m): (&Material, &MaterialSetup),
        out: &mut Batch,
    ) {
        let key = self.polygon_key(3, || key_sum(self, ids));
        out.counts.drawn += 1;
        let paint = PolygonPaint {
            texture: m.texture,
            sampler: material.sampler,
            alpha_cutoff: m.alpha_cutoff,
            constant_color: Some(color),
            door: self.door,
            lod,
        };
        let rows = t.0.rows();
        let first = out.push_small(t, m.texture.is_some());
        out.polys.push(DrawPolygon::packed(first, 3, out.tag, rows, true, &paint, packed));
        if self.ordered {
            out.keys.push(key);
        }
    }
}
