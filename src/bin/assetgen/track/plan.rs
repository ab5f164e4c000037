//! The plan of the centreline (straights between corners rounded by arcs) and the height profile along it.

use glam::Vec2;

use super::util::{cross2, left, loop_dist, other, smoothstep};

#[derive(Clone, Copy, Debug)]
enum Piece {
    /// A straight from `p0` along `d`.
    Line { p0: Vec2, d: Vec2 },
    /// An arc from `p0` leaving along `d`, bending toward `side` with radius `r`; `sign` is +1 for left.
    Arc { p0: Vec2, d: Vec2, side: Vec2, r: f32, sign: f32 },
}

#[derive(Clone, Copy, Debug)]
struct Segment {
    s0: f32,
    len: f32,
    piece: Piece,
}

/// The closed centreline in plan: straights between corners rounded by arcs.
pub(super) struct Plan {
    segs: Vec<Segment>,
    pub(super) length: f32,
}

impl Plan {
    pub(super) fn new(corners: &[(f32, f32, f32)]) -> std::io::Result<Plan> {
        let n = corners.len();
        let pt = |i: usize| Vec2::new(corners[i % n].0, corners[i % n].1);
        // Per corner: incoming and outgoing directions, signed turn, tangent length.
        let mut fillets = vec![];
        for (i, c) in corners.iter().enumerate() {
            let p = pt(i);
            let a = (p - pt(i + n - 1)).normalize_or_zero();
            let b = (pt(i + 1) - p).normalize_or_zero();
            let turn = libm::atan2f(left(a).dot(b), a.dot(b));
            fillets.push((p, a, b, turn, c.2 * libm::tanf(turn.abs() / 2.0), c.2));
        }
        let mut segs = vec![];
        let mut s = 0.0;
        for (i, &(p, a, _, turn, t, r)) in fillets.iter().enumerate() {
            let (q, _, qb, _, qt, _) = fillets[(i + n - 1) % n];
            let start = q + qb * qt;
            let end = p - a * t;
            let len = (end - start).dot(a);
            if len < 0.0 {
                return Err(other(format!("corner {i} does not fit its neighbours")));
            }
            segs.push(Segment { s0: s, len, piece: Piece::Line { p0: start, d: a } });
            s += len;
            let sign = if turn >= 0.0 { 1.0 } else { -1.0 };
            let len = r * turn.abs();
            segs.push(Segment { s0: s, len, piece: Piece::Arc { p0: end, d: a, side: left(a) * sign, r, sign } });
            s += len;
        }
        Ok(Plan { segs, length: s })
    }

    /// Position, direction and signed curvature (positive turning left) at distance `s`.
    pub(super) fn eval(&self, s: f32) -> (Vec2, Vec2, f32) {
        let s = s.rem_euclid(self.length);
        let k = self.segs.partition_point(|g| g.s0 + g.len <= s).min(self.segs.len() - 1);
        let g = self.segs[k];
        let u = s - g.s0;
        match g.piece {
            Piece::Line { p0, d } => (p0 + d * u, d, 0.0),
            Piece::Arc { p0, d, side, r, sign } => {
                let th = u / r;
                (
                    p0 + (d * libm::sinf(th) + side * (1.0 - libm::cosf(th))) * r,
                    d * libm::cosf(th) + side * libm::sinf(th),
                    sign / r,
                )
            }
        }
    }

    /// Where the straight into corner `edge` crosses another straight: (its s, the other's s, the point, its
    /// direction, the other's direction).
    pub(super) fn crossing(&self, edge: usize) -> Option<(f32, f32, Vec2, Vec2, Vec2)> {
        let g = self.segs.get(2 * edge)?;
        let Piece::Line { p0, d } = g.piece else { return None };
        for (j, h) in self.segs.iter().enumerate() {
            let Piece::Line { p0: q0, d: e } = h.piece else { continue };
            let den = cross2(d, e);
            if j == 2 * edge || den.abs() < 1e-4 {
                continue;
            }
            let w = q0 - p0;
            let (t, u) = (cross2(w, e) / den, cross2(w, d) / den);
            if (0.0..=g.len).contains(&t) && (0.0..=h.len).contains(&u) {
                return Some((g.s0 + t, h.s0 + u, p0 + d * t, d, e));
            }
        }
        None
    }

    /// Distance along the plan of `frac` of segment `seg`.
    pub(super) fn at_segment(&self, seg: usize, frac: f32) -> f32 {
        self.segs.get(seg).map_or(0.0, |g| g.s0 + g.len * frac)
    }
}

/// Heights along the plan: smooth bumps of (centre, height, half-length of the top, length of each ramp).
pub(super) struct Profile {
    pub(super) bumps: Vec<(f32, f32, f32, f32)>,
    pub(super) length: f32,
}

impl Profile {
    pub(super) fn height(&self, s: f32) -> f32 {
        let bump = |&(c, h, top, ramp): &(f32, f32, f32, f32)| {
            h * smoothstep(0.0, 1.0, (top + ramp - loop_dist(s, c, self.length)) / ramp)
        };
        self.bumps.iter().map(bump).sum()
    }
}
