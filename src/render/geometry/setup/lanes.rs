//! Polygon set-up eight polygons at a time: the small triangles among them set up in vector lanes
//! ([`super::small_setup_avx2`]), everything else one polygon at a time, in order.
//!
//! A group of eight consecutive polygons is taken to the lanes when they are triangles of one material
//! whose flat triangles have the direct small-triangle path; the lanes then say which of them are small
//! triangles that need no clipping, and set up their records. Each of those is finished here as the
//! one-polygon path finishes it (its colour compared, culled, its level of detail, key and draw polygon),
//! and any other polygon of the group goes through that path, so the batch written is the same, record for
//! record and count for count, as the one-polygon loop writes.

use std::ops::Range;

use super::{MaterialSetup, ObjectSetup, SetupScratch, culled};
use crate::render::core::batch::Batch;
use crate::render::geometry::small_setup_avx2::{LANES, set_up};
use crate::render::geometry::vertex::SetupVertex;
use crate::render::simd::Avx2;

/// Groups of eight polygons set up one at a time after a group where the lanes found few small triangles.
const SKIPPED: u32 = 3;

impl ObjectSetup<'_> {
    /// Sets up the whole groups of eight of polygons `range` into `out` and returns where they end (the
    /// caller sets up the rest one at a time).
    pub(super) fn run_lanes(
        &self,
        avx2: Avx2,
        range: Range<usize>,
        out: &mut Batch,
        scratch: &mut SetupScratch,
        cached: &mut Option<MaterialSetup>,
    ) -> usize {
        // Groups where the lanes found few small triangles (big polygons near the camera, mixed materials,
        // quads) are cheaper one polygon at a time: after one, the next few groups are.
        let (mut k, mut skip) = (range.start, 0);
        while k + LANES <= range.end {
            if skip > 0 {
                skip -= 1;
                self.one_by_one(k, out, scratch, cached);
            } else if self.eight(avx2, k, out, scratch, cached) < LANES * 3 / 4 {
                skip = SKIPPED;
            }
            k += LANES;
        }
        k
    }

    /// Sets up the eight polygons at positions `k..k + 8` into `out`, and returns how many of them the lanes
    /// set up (or culled) as small triangles.
    #[inline]
    fn eight(
        &self,
        avx2: Avx2,
        k: usize,
        out: &mut Batch,
        scratch: &mut SetupScratch,
        cached: &mut Option<MaterialSetup>,
    ) -> usize {
        let first = self.polygon_at(k).and_then(|p| self.material_of(p, cached));
        let Some((material, m)) = first.filter(|(_, m)| m.lanes()) else {
            self.one_by_one(k, out, scratch, cached);
            return 0;
        };
        // The lanes' corners; a lane whose polygon is not a triangle of this material keeps corners 0 and is
        // not taken.
        let mut ids = [[0u32; LANES]; 3];
        let mut taken = 0u32;
        for l in 0..LANES {
            let Some(poly) = self.polygon_at(k + l) else { continue };
            if let &[a, b, c] = self.mesh.polygon_indices(poly)
                && poly.material == m.index
                && self.needs_no_clipping([a, b, c])
            {
                for (corner, i) in ids.iter_mut().zip([a, b, c]) {
                    corner[l] = i;
                }
                taken |= 1 << l;
            }
        }
        // Fewer than three quarters of the lanes would not pay for the vector set-up.
        if taken.count_ones() < LANES as u32 * 3 / 4 {
            self.one_by_one(k, out, scratch, cached);
            return 0;
        }
        #[cfg(test)]
        tests::GROUPS.with(|g| g.set(g.get() + 1));
        let base = material.base_color.to_array();
        let lanes = set_up(avx2, (self.vertices, self.mesh.vertices()), &ids, base, self.small_frame());
        let small = taken & lanes.fit;
        let mut done = 0;
        for l in 0..LANES {
            if small >> l & 1 == 0 {
                self.polygon_outlined(k + l, out, scratch, cached);
                continue;
            }
            let corners = ids.map(|c| c[l] as usize);
            let Some(color) = self.flat_color(&corners, material) else {
                self.polygon_outlined(k + l, out, scratch, cached);
                continue;
            };
            done += 1;
            if culled(i64::from(lanes.area[l]), material, &mut out.counts) {
                continue;
            }
            let packed = lanes.packed[l] as u32;
            self.push_small(lanes.triangle(l), &corners, (color, 0, packed), (material, &m), out);
        }
        done
    }

    /// Whether the corners `ids` are finite and projected, none needs clipping and they are not all outside
    /// one clip plane: the per-polygon loop's checks before a small triangle's set-up, on the four flag
    /// bytes of each corner at once.
    #[inline(always)]
    fn needs_no_clipping(&self, ids: [u32; 3]) -> bool {
        let v = self.vertices;
        let [a, b, c] = [v[ids[0] as usize].flags(), v[ids[1] as usize].flags(), v[ids[2] as usize].flags()];
        let (all, any) = (a & b & c, a | b | c);
        (all & SetupVertex::FINITE_PROJECTED_OUTSIDE) | (any & SetupVertex::CUT) == SetupVertex::FINITE_PROJECTED
    }

    /// Sets up polygons `k..k + 8` one at a time.
    fn one_by_one(&self, k: usize, out: &mut Batch, scratch: &mut SetupScratch, cached: &mut Option<MaterialSetup>) {
        for l in 0..LANES {
            self.polygon_outlined(k + l, out, scratch, cached);
        }
    }

    /// [`Self::polygon`] as a call: the polygons the lanes hand back are few, and one inlined copy of the
    /// one-polygon path (in `run`) keeps the code small.
    #[inline(never)]
    fn polygon_outlined(
        &self,
        k: usize,
        out: &mut Batch,
        scratch: &mut SetupScratch,
        cached: &mut Option<MaterialSetup>,
    ) {
        self.polygon(k, out, scratch, cached);
    }
}

#[cfg(test)]
#[path = "lanes_tests.rs"]
mod tests;
