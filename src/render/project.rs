//! Polygon set-up: gather a polygon's vertices, clip it, project and snap it to [`Fx28_4`], cull back faces
//! and zero areas, and split non-monotone polygons, producing [`DrawPolygon`]s for the ordering stage.
//!
//! One object's polygons can be set up in pieces on several threads, each piece into its own [`Batch`];
//! appending the batches in order gives exactly what one pass would.

use std::ops::Range;

use glam::Vec4;

use super::DepthKey;
use super::clip::{ClipResult, ClipVertex, ClipVolume, VIEW_DEPTH, clip_polygon};
use super::fixed::Fx28_4;
use super::mesh::{AlphaMode, Mesh};
use super::monotone::triangulate;
use super::pipeline::{DrawPolygon, slope_scaled_bias};
use super::scanline::{ATTRS, ScreenVertex, is_y_monotone, signed_area2, slot};
use super::stats::Stats;

/// Polygons dropped or changed during set-up, by reason.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Counts {
    invalid: u64,
    outside: u64,
    clipped: u64,
    degenerate: u64,
    backface: u64,
    drawn: u64,
    split: u64,
}

impl Counts {
    /// The polygon counts of a frame's statistics.
    fn from_stats(s: &Stats) -> Self {
        Self {
            invalid: s.polygons_invalid,
            outside: s.polygons_outside,
            clipped: s.polygons_clipped,
            degenerate: s.polygons_degenerate,
            backface: s.polygons_backface,
            drawn: s.polygons_drawn,
            split: s.polygons_split,
        }
    }

    /// Adds these counts to a frame's statistics.
    pub(super) fn add_to(&self, stats: &mut Stats) {
        stats.polygons_invalid += self.invalid;
        stats.polygons_outside += self.outside;
        stats.polygons_clipped += self.clipped;
        stats.polygons_degenerate += self.degenerate;
        stats.polygons_backface += self.backface;
        stats.polygons_drawn += self.drawn;
        stats.polygons_split += self.split;
    }
}

/// Set-up output (screen vertices and the polygons indexing them) and the scratch buffers that make it.
#[derive(Debug, Default)]
pub(super) struct Batch {
    pub(super) screen: Vec<ScreenVertex>,
    pub(super) polys: Vec<DrawPolygon>,
    pub(super) counts: Counts,
    clip_in: Vec<ClipVertex>,
    clip_out: Vec<ClipVertex>,
    clip_scratch: Vec<ClipVertex>,
    piece: Vec<ScreenVertex>,
    tris: Vec<[usize; 3]>,
}

impl Batch {
    /// Empties the output, keeping the allocations.
    pub(super) fn clear(&mut self) {
        self.screen.clear();
        self.polys.clear();
        self.counts = Counts::default();
    }

    /// Moves another batch's output to the end of this one, re-basing its vertex indices.
    pub(super) fn append(&mut self, other: &mut Batch) {
        let base = self.screen.len() as u32;
        self.screen.append(&mut other.screen);
        self.polys.extend(other.polys.drain(..).map(|p| DrawPolygon { first: p.first + base, ..p }));
        let mut stats = Stats::default();
        self.counts.add_to(&mut stats);
        std::mem::take(&mut other.counts).add_to(&mut stats);
        self.counts = Counts::from_stats(&stats);
    }
}

/// One object's transformed vertices and what set-up needs to know about the frame.
pub(super) struct ObjectSetup<'a> {
    /// The mesh drawn (with its split pieces, for `view-lists`).
    pub(super) mesh: &'a Mesh,
    /// The stored drawing order of its polygons, if one applies.
    pub(super) stored: Option<&'a [u32]>,
    /// Clip-space positions of the mesh's vertices.
    pub(super) clip_pos: &'a [Vec4],
    /// View depths of the mesh's vertices.
    pub(super) view_depth: &'a [f32],
    /// The clip volume.
    pub(super) volume: &'a ClipVolume,
    /// The ordering key rule.
    pub(super) key: DepthKey,
    /// Perspective (depth is `1/w`) or orthographic camera.
    pub(super) perspective: bool,
    /// Whether attributes are divided by `w` for perspective-correct interpolation.
    pub(super) perspective_attrs: bool,
    /// Frame width and height in pixels.
    pub(super) size: (f32, f32),
    /// The key of every polygon when the object is drawn in a stored order.
    pub(super) object_key: Option<f32>,
    /// How many textures the draw list has.
    pub(super) textures: usize,
    /// Draw with the screen door (the ghost car).
    pub(super) see_through: bool,
}

impl ObjectSetup<'_> {
    /// Sets up polygons `range` (positions in the stored order, or polygon indices) into `out`.
    pub(super) fn run(&self, range: Range<usize>, out: &mut Batch) {
        for k in range {
            let Some(poly) = self.mesh.polygons().get(self.stored.map_or(k, |o| o[k] as usize)) else { continue };
            let idx = self.mesh.polygon_indices(poly);
            let material = self.mesh.materials().get(poly.material as usize).cloned().unwrap_or_default();
            out.clip_in.clear();
            let mut finite = true;
            for &i in idx {
                let i = i as usize;
                let v = &self.mesh.vertices()[i];
                let pos = self.clip_pos[i];
                let c = v.color * material.base_color;
                finite &= pos.is_finite() && self.view_depth[i].is_finite();
                out.clip_in.push(ClipVertex { pos, attrs: [v.uv.x, v.uv.y, c.x, c.y, c.z, c.w, self.view_depth[i]] });
            }
            if !finite {
                out.counts.invalid += 1;
                continue;
            }
            match clip_polygon(&out.clip_in, self.volume, &mut out.clip_out, &mut out.clip_scratch) {
                ClipResult::Outside => {
                    out.counts.outside += 1;
                    continue;
                }
                ClipResult::Clipped => out.counts.clipped += 1,
                ClipResult::Inside => {}
            }
            // Project and snap.
            let first = out.screen.len();
            let mut ok = true;
            let mut key = match self.key {
                DepthKey::Avg => 0.0,
                DepthKey::Min => f32::INFINITY,
                DepthKey::Max => f32::NEG_INFINITY,
            };
            for cv in &out.clip_out {
                let p = cv.pos;
                let q = 1.0 / p.w;
                let sx = (p.x * q + 1.0) * 0.5 * self.size.0;
                let sy = (1.0 - p.y * q) * 0.5 * self.size.1;
                let (Some(x), Some(y)) = (Fx28_4::from_f32(sx), Fx28_4::from_f32(sy)) else {
                    ok = false;
                    break;
                };
                if !(p.w > 0.0 && q.is_finite()) {
                    ok = false;
                    break;
                }
                let depth = if self.perspective { q } else { 0.5 * (1.0 - p.z * q) };
                let a = &cv.attrs;
                let m = if self.perspective_attrs { q } else { 1.0 };
                let mut attrs = [0.0; ATTRS];
                attrs[slot::DEPTH] = depth;
                attrs[slot::Q] = m;
                attrs[slot::S] = a[0] * m;
                attrs[slot::T] = a[1] * m;
                for c in 0..4 {
                    attrs[slot::RGBA + c] = a[2 + c] * m;
                }
                out.screen.push(ScreenVertex { x, y, attrs });
                let d = a[VIEW_DEPTH];
                key = match self.key {
                    DepthKey::Avg => key + d,
                    DepthKey::Min => key.min(d),
                    DepthKey::Max => key.max(d),
                };
            }
            let n = out.screen.len() - first;
            if !ok {
                out.screen.truncate(first);
                out.counts.invalid += 1;
                continue;
            }
            if self.key == DepthKey::Avg {
                key /= n as f32;
            }
            if material.depth_bias > 0 {
                slope_scaled_bias(&mut out.screen[first..], material.depth_bias);
            }
            // A stored order keeps the object's polygons together, placed by the object's depth.
            if let Some(k) = self.object_key {
                key = k;
            }
            let area = signed_area2(&out.screen[first..]);
            if area == 0 {
                out.screen.truncate(first);
                out.counts.degenerate += 1;
                continue;
            }
            if area > 0 && !material.double_sided {
                out.screen.truncate(first);
                out.counts.backface += 1;
                continue;
            }
            out.counts.drawn += 1;
            let texture = material.texture.filter(|&t| t < self.textures).map(|t| t as u32);
            let alpha_cutoff = match material.alpha_mode {
                AlphaMode::Opaque => None,
                AlphaMode::Mask { cutoff } => Some(cutoff),
            };
            let first_color = out.clip_out.first().map(|v| [v.attrs[2], v.attrs[3], v.attrs[4], v.attrs[5]]);
            let constant_color = first_color
                .filter(|c| out.clip_out.iter().all(|v| [v.attrs[2], v.attrs[3], v.attrs[4], v.attrs[5]] == *c));
            let base = DrawPolygon {
                first: first as u32,
                count: n as u32,
                key,
                texture,
                sampler: material.sampler,
                alpha_cutoff,
                constant_color,
                screen_door: self.see_through,
            };
            if is_y_monotone(&out.screen[first..]) {
                out.polys.push(base);
            } else {
                out.counts.split += 1;
                out.tris.clear();
                out.piece.clear();
                out.piece.extend_from_slice(&out.screen[first..]);
                triangulate(&out.piece, area.signum(), &mut out.tris);
                out.screen.truncate(first);
                for t in &out.tris {
                    let f = out.screen.len() as u32;
                    out.screen.extend(t.iter().map(|&i| out.piece[i]));
                    out.polys.push(DrawPolygon { first: f, count: 3, ..base });
                }
            }
        }
    }
}
