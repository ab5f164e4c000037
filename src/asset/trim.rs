//! Cut-out polygons trimmed at load to the part of their texture that can be drawn.
//!
//! A cut-out (a tree, a fence, a sign with a shaped edge) is a quad whose texture is mostly transparent,
//! and every pixel of the transparent part still costs the fill a depth test, a texel fetch and the alpha
//! test that throws it away. So each polygon of an alpha-masked, textured material is clipped to the
//! convex hull of the level-0 texels that can pass the test around its texture region (the region and one
//! texel beyond it, read through the sampler's wrap as the fill reads them), each texel widened by one
//! texel on every side (a bilinear or box-filtered sample reaches less than one texel past the texel it
//! weighs), the hull first simplified to at most [`MAX_HULL`] corners by pushing edges outward, never
//! inward.
//!
//! The clipped polygon lies in the original's plane, its corners the original's that are inside and points
//! interpolated along the original's edges, so a pixel outside it could not pass the alpha test at level 0
//! with one sample at its centre and a filter reaching at most a texel. What can still differ from the
//! whole polygon: a pixel whose new corners' rounding moves a texel boundary or the card's edge by a
//! rounding step; a polygon whose level of detail (its texels over its pixels, which under perspective
//! is not the same for a part as for the whole) crosses to the next level; a coarse level's block that
//! passed beyond the hull (the trimmed card draws the level-0 outline the reference integrates); and
//! filters that reach further at level 0 (an anisotropic probe, a coverage sample shaded at a pixel's
//! centre far from it).
//!
//! A polygon is kept whole when trimming it would not pay (less than a tenth of its area cut, or its
//! texture coordinates all one point), when it shares an edge with another polygon of its primitive (a
//! neighbour cut elsewhere on that edge would leave a crack), when its texture region crosses a tile edge
//! or leaves `0..1` unrepeated, when the region is larger than [`MAX_REGION_SIDE`] a side or
//! [`MAX_REGION_TEXELS`], when the load has scanned [`MAX_LOAD_TEXELS`] or kept [`MAX_HULLS`] hulls, or
//! when nothing in the region can pass (the drawing then decides, as without trimming).

use std::collections::BTreeMap;

use glam::{DVec2, Vec2};

use crate::render::{Sampler, Texture, Vertex, Wrap};

/// The most corners a simplified hull keeps (each one more half-plane to clip by).
pub const MAX_HULL: usize = 5;

/// The longest side (texels) of a texture region scanned for one polygon.
pub const MAX_REGION_SIDE: i64 = 4096;

/// The largest texture region (texels) scanned for one polygon; a larger one keeps its polygon whole.
pub const MAX_REGION_TEXELS: u64 = 1 << 22;

/// The most texels one load scans for hulls over all its polygons (regions already seen are free).
pub const MAX_LOAD_TEXELS: u64 = 1 << 26;

/// The most hulls one load keeps; later regions keep their polygons whole.
pub const MAX_HULLS: usize = 1 << 16;

/// The furthest tile (texture coordinates' whole part) trimmed: beyond it `f32` coordinates keep too few
/// bits below the texel for the one-texel margin to hold.
const MAX_TILE: f64 = 1024.0;

/// A trimmed polygon must cut at least this share of the original's area to replace it.
const MIN_CUT: f64 = 0.1;

/// One texture region's hull, in texel coordinates of its tile: `None` when nothing in it can pass.
type Hull = Option<Vec<DVec2>>;

/// A corner of a trimmed polygon: the original's corner `Some(k)` (its index in the polygon), or a new
/// point on one of its edges.
pub(super) type Corner = (Vertex, Option<usize>);

/// What a hull is cached by: texture, wraps, tile-relative texel rectangle and alpha threshold.
type Key = (usize, [u8; 2], [i64; 4], u32);

/// The hulls found so far in one load.
#[derive(Default)]
pub(super) struct Trimmer {
    hulls: BTreeMap<Key, Hull>,
    scanned: u64,
}

fn wrap_code(w: Wrap) -> u8 {
    match w {
        Wrap::Repeat => 0,
        Wrap::ClampToEdge => 1,
        Wrap::MirroredRepeat => 2,
    }
}

impl Trimmer {
    /// The polygon `poly` (corners in order) clipped to the drawable part of `texture` (draw-list index
    /// `index`) under `sampler`, for a material drawn where texel alpha times `alpha` (the base colour's
    /// alpha) is at least `cutoff`; `None` keeps the polygon as it is.
    pub(super) fn trim(
        &mut self,
        (texture, index): (&Texture, usize),
        sampler: Sampler,
        (alpha, cutoff): (f32, f32),
        poly: &[Vertex],
    ) -> Option<Vec<Corner>> {
        let most_alpha = poly.iter().map(|v| v.color.w).fold(0.0f32, f32::max) * alpha;
        if !(cutoff > 0.0 && most_alpha > 0.0 && most_alpha.is_finite()) || poly.len() < 3 {
            return None;
        }
        // A texel may pass when its alpha times the most the colours can give reaches the cutoff (with room
        // for a merged quad's colours, affine to 1e-3, to exceed its corners' a little).
        let threshold = cutoff / most_alpha * (1.0 - 2e-3);
        let (lo, hi) = uv_bounds(poly)?;
        let (w, h) = (texture.width() as f64, texture.height() as f64);
        let tile = DVec2::new(tile_of(lo.x, hi.x, sampler.wrap_s)?, tile_of(lo.y, hi.y, sampler.wrap_t)?);
        // The texels the region's samples can weigh: its own and one beyond it on every side.
        let rect = [
            ((lo.x - tile.x) * w).floor() as i64 - 1,
            ((lo.y - tile.y) * h).floor() as i64 - 1,
            ((hi.x - tile.x) * w).ceil() as i64 + 1,
            ((hi.y - tile.y) * h).ceil() as i64 + 1,
        ];
        let (across, down) = (rect[2] - rect[0], rect[3] - rect[1]);
        let area = across as u64 * down as u64;
        if across > MAX_REGION_SIDE || down > MAX_REGION_SIDE || area > MAX_REGION_TEXELS {
            return None;
        }
        let key = (index, [wrap_code(sampler.wrap_s), wrap_code(sampler.wrap_t)], rect, threshold.to_bits());
        if !self.hulls.contains_key(&key) {
            let scanned = self.scanned.saturating_add(area);
            if scanned > MAX_LOAD_TEXELS || self.hulls.len() >= MAX_HULLS {
                return None;
            }
            self.scanned = scanned;
            self.hulls.insert(key, hull_of(texture, sampler, rect, threshold));
        }
        let hull = self.hulls.get(&key)?.as_ref()?;
        // The hull in the polygon's texture coordinates.
        let scale = DVec2::new(w, h);
        let hull_uv: Vec<DVec2> = hull.iter().map(|&p| p / scale + tile).collect();
        let cut = clip(poly, &hull_uv);
        let uv = |c: &[Corner]| c.iter().map(|(v, _)| v.uv.as_dvec2()).collect::<Vec<_>>();
        let before = polygon_area(&poly.iter().map(|v| v.uv.as_dvec2()).collect::<Vec<_>>()).abs();
        let after = polygon_area(&uv(&cut)).abs();
        (cut.len() >= 3 && before > 0.0 && after <= before * (1.0 - MIN_CUT)).then_some(cut)
    }
}

/// The box of the polygon's texture coordinates, if they are all finite.
fn uv_bounds(poly: &[Vertex]) -> Option<(DVec2, DVec2)> {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for v in poly {
        let uv = v.uv.as_dvec2();
        if !uv.is_finite() {
            return None;
        }
        lo = lo.min(uv);
        hi = hi.max(uv);
    }
    Some((lo, hi))
}

/// The whole-number tile holding `lo..hi` along one axis: any one tile when the texture repeats, only
/// `0..1` otherwise (a clamped texture stretches its edge texels outside it, a mirrored one flips).
fn tile_of(lo: f64, hi: f64, wrap: Wrap) -> Option<f64> {
    let tile = lo.floor();
    let fits = hi <= tile + 1.0 && tile.abs() <= MAX_TILE && (wrap == Wrap::Repeat || tile == 0.0);
    fits.then_some(tile)
}

/// The convex hull of the texels in `rect` (tile-relative, read through `sampler`'s wrap) whose alpha
/// reaches `threshold`, each widened by one texel, simplified to [`MAX_HULL`] corners; `None` when no
/// texel reaches it.
fn hull_of(texture: &Texture, sampler: Sampler, [x0, y0, x1, y1]: [i64; 4], threshold: f32) -> Hull {
    let passes = |x: i64, y: i64| {
        // The region's sides are at most `MAX_REGION_SIDE` and its tile at most `MAX_TILE` away: in range.
        (texture.texel(x as i32, y as i32, sampler) >> 24) as f32 / 255.0 >= threshold
    };
    let mut points = Vec::new();
    for y in y0..y1 {
        let (Some(first), Some(last)) = ((x0..x1).find(|&x| passes(x, y)), (x0..x1).rev().find(|&x| passes(x, y)))
        else {
            continue;
        };
        let (left, right, top, bottom) = ((first - 1) as f64, (last + 2) as f64, (y - 1) as f64, (y + 2) as f64);
        points.extend([(left, top), (left, bottom), (right, top), (right, bottom)].map(DVec2::from));
    }
    let hull = convex_hull(points);
    (hull.len() >= 3).then(|| simplify(hull, MAX_HULL))
}

fn cross(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    (a - o).perp_dot(b - o)
}

/// Andrew's monotone chain: the hull's corners in one turning order, without collinear points.
fn convex_hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let mut hull: Vec<DVec2> = Vec::with_capacity(points.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Fewer corners for a convex polygon, by the cheapest edge removals: edge `i`..`i+1` goes, and its two
/// neighbouring edges are extended to meet outside it, so the polygon only grows. An edge whose
/// neighbours do not meet outside (they turn half a circle or more between them) is not removable.
fn simplify(mut hull: Vec<DVec2>, most: usize) -> Vec<DVec2> {
    while hull.len() > most {
        let n = hull.len();
        let best = (0..n)
            .filter_map(|i| {
                let (a, b, c, d) = (hull[(i + n - 1) % n], hull[i], hull[(i + 1) % n], hull[(i + 2) % n]);
                let meet = meeting(a, b, c, d)?;
                Some((cross(b, meet, c).abs() * 0.5, i, meet))
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let Some((_, i, meet)) = best else { break };
        // Corners `i` and `i + 1` become the one meeting point.
        hull[i] = meet;
        hull.remove((i + 1) % n);
    }
    hull
}

/// Where the line `a`->`b` extended past `b` meets the line `d`->`c` extended past `c`, when it does.
fn meeting(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Option<DVec2> {
    let (r, s) = (b - a, c - d);
    let denom = r.perp_dot(s);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (c - b).perp_dot(s) / denom;
    let u = (c - b).perp_dot(r) / denom;
    (t >= 0.0 && u >= 0.0).then(|| b + r * t)
}

/// The polygon clipped to the convex `hull` (in texture coordinates, either winding), each new corner
/// interpolated along the edge it cuts (Sutherland-Hodgman); the polygon's winding is kept.
fn clip(poly: &[Vertex], hull: &[DVec2]) -> Vec<Corner> {
    let turn = polygon_area(hull).signum();
    let mut out: Vec<Corner> = poly.iter().enumerate().map(|(k, v)| (*v, Some(k))).collect();
    for k in 0..hull.len() {
        let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
        let side = |v: &Vertex| cross(a, b, v.uv.as_dvec2()) * turn;
        let input = std::mem::take(&mut out);
        for (i, cur) in input.iter().enumerate() {
            let next = &input[(i + 1) % input.len()];
            let (sc, sn) = (side(&cur.0), side(&next.0));
            if sc >= 0.0 {
                out.push(*cur);
            }
            // Strictly across: a corner on the line is kept once, not doubled.
            if (sc > 0.0 && sn < 0.0) || (sc < 0.0 && sn > 0.0) {
                out.push((lerp(&cur.0, &next.0, sc / (sc - sn)), None));
            }
        }
        if out.len() < 3 {
            return Vec::new();
        }
    }
    out
}

/// The point a share `t` of the way from `p` to `q`, every attribute as `p + (q - p) t` (so an attribute
/// the two ends share, such as a polygon's one colour, keeps its exact bits: the fill's fast paths need a
/// colour that does not change across the polygon).
fn lerp(p: &Vertex, q: &Vertex, t: f64) -> Vertex {
    let mix = |a: f32, b: f32| (f64::from(a) + (f64::from(b) - f64::from(a)) * t) as f32;
    let position = glam::Vec3::new(
        mix(p.position.x, q.position.x),
        mix(p.position.y, q.position.y),
        mix(p.position.z, q.position.z),
    );
    let uv = Vec2::new(mix(p.uv.x, q.uv.x), mix(p.uv.y, q.uv.y));
    let color = glam::Vec4::new(
        mix(p.color.x, q.color.x),
        mix(p.color.y, q.color.y),
        mix(p.color.z, q.color.z),
        mix(p.color.w, q.color.w),
    );
    Vertex { position, uv, color }
}

/// The signed area of a polygon's corners (its sign tells the winding).
fn polygon_area(p: &[DVec2]) -> f64 {
    (0..p.len()).map(|i| p[i].perp_dot(p[(i + 1) % p.len()])).sum::<f64>() * 0.5
}

#[cfg(test)]
mod tests {
    use glam::{Vec3, Vec4};

    use super::*;

    const CLAMP: Sampler = Sampler { wrap_s: Wrap::ClampToEdge, wrap_t: Wrap::ClampToEdge };

    /// A 32x32 texture, clear but for an opaque disc of radius 6 texels centred at (20, 12).
    fn disc() -> Texture {
        let texels = (0..32 * 32)
            .map(|i| {
                let (x, y) = ((i % 32) as f32 + 0.5, (i / 32) as f32 + 0.5);
                if (x - 20.0).powi(2) + (y - 12.0).powi(2) < 36.0 { 0xff40_8020 } else { 0x0040_8020 }
            })
            .collect();
        Texture::new(32, 32, texels).unwrap()
    }

    /// A quad in the XY plane from (0, 0) to (8, 4) with texture coordinates 0..1, v down the texture.
    fn quad(color: Vec4) -> Vec<Vertex> {
        let corner =
            |x: f32, y: f32| Vertex { position: Vec3::new(x * 8.0, y * 4.0, 1.5), uv: Vec2::new(x, 1.0 - y), color };
        vec![corner(0.0, 0.0), corner(1.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0)]
    }

    /// The trimmed polygon's corners, checking that each kept corner is the original's it names.
    fn corners(cut: Option<Vec<Corner>>, original: &[Vertex]) -> Vec<Vertex> {
        let cut = cut.expect("trimmed");
        for (v, k) in &cut {
            if let Some(k) = k {
                assert_eq!(original[*k], *v);
            }
        }
        cut.into_iter().map(|(v, _)| v).collect()
    }

    fn uv_area(poly: &[Vertex]) -> f64 {
        polygon_area(&poly.iter().map(|v| v.uv.as_dvec2()).collect::<Vec<_>>()).abs()
    }

    fn inside(poly: &[Vertex], p: DVec2) -> bool {
        let uv: Vec<DVec2> = poly.iter().map(|v| v.uv.as_dvec2()).collect();
        let turn = polygon_area(&uv).signum();
        (0..uv.len()).all(|i| cross(uv[i], uv[(i + 1) % uv.len()], p) * turn >= -1e-9)
    }

    #[test]
    fn a_cut_out_keeps_every_texel_that_can_pass_and_a_texel_around_it() {
        let tex = disc();
        let cut = corners(Trimmer::default().trim((&tex, 0), CLAMP, (1.0, 0.5), &quad(Vec4::ONE)), &quad(Vec4::ONE));
        assert!(cut.len() <= MAX_HULL + 4, "{} corners", cut.len());
        // Every opaque texel's square, widened by one texel, lies inside; a texel three away does not.
        for (i, t) in tex.texels().iter().enumerate() {
            let (x, y) = ((i % 32) as f64, (i / 32) as f64);
            if t >> 24 == 0xff {
                for (cx, cy) in [(x - 1.0, y - 1.0), (x + 2.0, y - 1.0), (x - 1.0, y + 2.0), (x + 2.0, y + 2.0)] {
                    assert!(inside(&cut, DVec2::new(cx, cy) / 32.0), "texel ({x}, {y}) cut off");
                }
            }
        }
        assert!(!inside(&cut, DVec2::new(20.5, 21.5) / 32.0));
        // A disc of 113 texels and its margin: far less than the quad's 1024.
        assert!(uv_area(&cut) * 1024.0 < 300.0, "{}", uv_area(&cut) * 1024.0);
    }

    #[test]
    fn new_corners_lie_in_the_plane_with_the_texture_where_it_was() {
        let tex = disc();
        let color = Vec4::new(0.3, 0.6, 0.9, 1.0);
        let cut = corners(Trimmer::default().trim((&tex, 0), CLAMP, (1.0, 0.5), &quad(color)), &quad(color));
        for v in &cut {
            // The quad maps u to x * 8 and v to (1 - y) * 4; the colour is the polygon's, bit for bit.
            assert!((v.position.x - v.uv.x * 8.0).abs() < 1e-5 && (v.position.y - (1.0 - v.uv.y) * 4.0).abs() < 1e-5);
            assert_eq!(v.position.z, 1.5);
            assert_eq!(v.color, color);
        }
        // The winding is kept.
        let area = |p: &[Vertex]| polygon_area(&p.iter().map(|v| v.position.truncate().as_dvec2()).collect::<Vec<_>>());
        assert!(area(&cut) > 0.0 && area(&quad(color)) > 0.0);
    }

    #[test]
    fn polygons_that_cannot_be_trimmed_stay_whole() {
        let tex = disc();
        let mut t = Trimmer::default();
        let whole = quad(Vec4::ONE);
        // Texture coordinates across a tile edge, or outside 0..1 without repeating.
        let mut shifted = whole.clone();
        shifted.iter_mut().for_each(|v| v.uv.x += 0.5);
        assert!(t.trim((&tex, 0), CLAMP, (1.0, 0.5), &shifted).is_none());
        let repeat = Sampler { wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat };
        assert!(t.trim((&tex, 0), repeat, (1.0, 0.5), &shifted).is_none());
        // Inside the next tile of a repeating texture it is trimmed as in the first.
        let mut next = whole.clone();
        next.iter_mut().for_each(|v| v.uv.x += 1.0);
        let cut = corners(t.trim((&tex, 0), repeat, (1.0, 0.5), &next), &next);
        assert!(cut.iter().all(|v| v.uv.x >= 1.0));
        // Nothing can pass (the colour's alpha halves every texel's), a cutoff of 0, NaN coordinates.
        assert!(t.trim((&tex, 0), CLAMP, (0.4, 0.5), &whole).is_none());
        assert!(t.trim((&tex, 0), CLAMP, (1.0, 0.0), &whole).is_none());
        let mut nan = whole.clone();
        nan[2].uv.y = f32::NAN;
        assert!(t.trim((&tex, 0), CLAMP, (1.0, 0.5), &nan).is_none());
        // Every corner on one texture coordinate (one texel stretched over the polygon): nothing to gain.
        let mut point = whole.clone();
        point.iter_mut().for_each(|v| v.uv = Vec2::new(0.6, 0.4));
        assert!(t.trim((&tex, 0), CLAMP, (1.0, 0.5), &point).is_none());
        // A fully opaque region has nothing to cut.
        let solid = Texture::new(4, 4, vec![0xff00_0000; 16]).unwrap();
        assert!(t.trim((&solid, 1), CLAMP, (1.0, 0.5), &whole).is_none());
    }

    #[test]
    fn texels_a_wrapping_sample_reads_beyond_the_region_are_kept() {
        // Opaque only in the last column (rows 10..20); the polygon covers the left half of the texture,
        // where a bilinear sample at its left edge weighs that column through the repeat.
        let texels = (0..32 * 32).map(|i| if i % 32 == 31 && (10..20).contains(&(i / 32)) { 0xff00_0000 } else { 0 });
        let tex = Texture::new(32, 32, texels.collect()).unwrap();
        let mut half = quad(Vec4::ONE);
        half.iter_mut().for_each(|v| v.uv.x *= 0.5);
        let repeat = Sampler { wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat };
        let cut = corners(Trimmer::default().trim((&tex, 0), repeat, (1.0, 0.5), &half), &half);
        assert!(inside(&cut, DVec2::new(0.5, 15.0) / 32.0) && inside(&cut, DVec2::new(0.5, 9.5) / 32.0));
        assert!(!inside(&cut, DVec2::new(3.0, 15.0) / 32.0));
        // Clamped, the column beyond the left edge is the first one, clear: nothing can pass, kept whole.
        assert!(Trimmer::default().trim((&tex, 0), CLAMP, (1.0, 0.5), &half).is_none());
    }

    #[test]
    fn simplifying_only_grows_the_hull() {
        // A 24-gon around a circle: simplified to 8 corners, it still holds every original corner.
        let ring: Vec<DVec2> = (0..24)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 24.0;
                DVec2::new(libm::cos(a) * 10.0, libm::sin(a) * 10.0)
            })
            .collect();
        let small = simplify(convex_hull(ring.clone()), 8);
        assert_eq!(small.len(), 8);
        for p in ring {
            assert!((0..8).all(|i| cross(small[i], small[(i + 1) % 8], p) >= -1e-9), "{p} outside");
        }
        assert!(polygon_area(&small) < 1.1 * std::f64::consts::PI * 100.0);
    }
}
