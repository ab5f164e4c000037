//! The circuit: samples along the centreline in racing order from the start line, with their cross-sections,
//! the bridge's layout and the corridor kept free of ground.

use glam::{Vec2, Vec3};

use super::plan::{Plan, Profile};
use super::spec::{APRON, BARRIER_OFFSET_RAISED, BRIDGE_HEIGHT, HALF_WIDTH, Layout, ROAD_LIFT, SAMPLE_STEP, SIDE};
use super::util::{cross2, loop_dist, other, smoothstep};

/// One centreline sample.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    /// Distance from the start line.
    pub(super) s: f32,
    /// Road surface at the centre.
    pub(super) p: Vec3,
    /// Horizontal unit vectors ahead and to the right.
    pub(super) fwd: Vec3,
    pub(super) right: Vec3,
    /// The banked lateral unit vector (to the right edge).
    pub(super) lat: Vec3,
    /// Roll of the cross-section, radians, positive raising the right side (left-hand corners).
    pub(super) bank: f32,
    /// Smoothed and exact curvature, positive turning left.
    kappa: f32,
    kappa_raw: f32,
    /// Height of the embankment under the road.
    pub(super) h: f32,
    /// The ground's level under the road (0 on the plain).
    pub(super) base: f32,
    /// Barrier offsets from the centreline, left and right.
    pub(super) bo: [f32; 2],
    /// Gravel run-off (outside of tight corners), left and right.
    pub(super) gravel: [bool; 2],
}

impl Sample {
    /// The cross-section at `s` from the plan position and direction, the smoothed and exact curvature, the
    /// embankment height and the bank angle: barriers at the layout's offset, further out on the outside of
    /// tight corners (gravel there) where the layout has run-off, closer in on embankments.
    fn new(
        layout: &Layout,
        s: f32,
        (pos, dir): (Vec2, Vec2),
        (kappa, kappa_raw): (f32, f32),
        (h, base): (f32, f32),
        bank: f32,
    ) -> Sample {
        let fwd = Vec3::new(dir.x, 0.0, dir.y);
        let right = Vec3::new(-dir.y, 0.0, dir.x);
        let lat = right * libm::cosf(bank) + Vec3::Y * libm::sinf(bank);
        // The roll pivots about the lower edge, so that edge stays at the lift above the ground.
        let p = Vec3::new(pos.x, h + ROAD_LIFT + HALF_WIDTH * libm::sinf(bank).abs() + base, pos.y);
        let extra = if layout.run_off { 10.0 * ((kappa.abs() - 0.006) * 80.0).clamp(0.0, 1.0) } else { 0.0 };
        let outside = usize::from(kappa > 0.0);
        let mut bo = [layout.barrier_offset; 2];
        let mut gravel = [false; 2];
        bo[outside] += extra;
        gravel[outside] = extra > 2.0;
        let raised = smoothstep(0.4, 2.0, h);
        let bo = bo.map(|b| b + (BARRIER_OFFSET_RAISED - b) * raised);
        Sample { s, p, fwd, right, lat, bank, kappa, kappa_raw, h, base, bo, gravel }
    }

    pub(super) fn edge(&self, side: usize) -> Vec3 {
        self.p + self.lat * (HALF_WIDTH * SIDE[side])
    }

    pub(super) fn out(&self, side: usize) -> Vec3 {
        self.right * SIDE[side]
    }

    /// The verge's outer line (foot of the barrier), level with the road edge.
    pub(super) fn verge(&self, side: usize) -> Vec3 {
        self.edge(side) + self.out(side) * (self.bo[side] - HALF_WIDTH)
    }
}

/// The ground level under the road at each of the `n` samples `step` apart from the start line (raw plan
/// distance `start`): linear between the relief's knots, 0 outside them, smoothed over 120 m so that the
/// grade changes gently; all 0 on a course without relief.
fn base_levels(layout: &Layout, plan: &Plan, start: f32, n: usize, step: f32) -> Vec<f32> {
    let Some(relief) = layout.relief else { return vec![0.0; n] };
    let race = |raw: f32| (raw - start).rem_euclid(plan.length);
    let knots: Vec<(f32, f32)> = relief.knots.iter().map(|&(seg, f, h)| (race(plan.at_segment(seg, f)), h)).collect();
    let linear = |s: f32| {
        let k = knots.partition_point(|&(ks, _)| ks <= s);
        match (k.checked_sub(1).map(|j| knots[j]), knots.get(k)) {
            (Some((s0, h0)), Some(&(s1, h1))) => h0 + (h1 - h0) * (s - s0) / (s1 - s0).max(1e-3),
            _ => 0.0,
        }
    };
    let raw: Vec<f32> = (0..n).map(|i| linear(i as f32 * step)).collect();
    let half = (60.0 / step).round() as usize;
    (0..n).map(|i| (0..=2 * half).map(|j| raw[(i + n + j - half) % n]).sum::<f32>() / (2 * half + 1) as f32).collect()
}

/// A position and frame on the centreline.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) p: Vec3,
    pub(super) fwd: Vec3,
    pub(super) right: Vec3,
    pub(super) lat: Vec3,
}

/// The circuit: samples along the centreline in racing order from the start line.
pub(super) struct Circuit {
    /// The course it was built from.
    pub(super) layout: &'static Layout,
    pub(super) length: f32,
    pub(super) step: f32,
    pub(super) samples: Vec<Sample>,
    /// Start-line distances of the crossing on the upper and the lower road, and its plan point.
    pub(super) upper_s: f32,
    pub(super) lower_s: f32,
    pub(super) cross_point: Vec2,
    /// Sample nearest the crossing on the upper road, and how many samples either side are open span.
    upper_i: usize,
    span: usize,
    /// Offset along the upper road of the pier rows either side of the lower road.
    pub(super) pier_offset: f32,
    /// Start-line distances where the viaduct's open span begins and ends (an empty range on the plain).
    pub(super) viaduct: (f32, f32),
    /// Start-line distances of the corners' apexes.
    pub(super) apex: Vec<f32>,
    /// How far from the centreline each sample's grass apron reaches, left and right.
    pub(super) apron: Vec<[f32; 2]>,
    /// Each sample's corridor, left and right ([`Circuit::reach`]).
    widths: Vec<[f32; 2]>,
    /// Texture repeat lengths that divide the lap exactly (road, kerb, barrier).
    pub(super) road_tile: f32,
    pub(super) kerb_tile: f32,
    pub(super) barrier_tile: f32,
}

impl Circuit {
    pub(super) fn new(layout: &'static Layout) -> std::io::Result<Circuit> {
        let plan = Plan::new(layout.corners)?;
        let length = plan.length;
        let start = plan.at_segment(2 * layout.start_edge, 0.0) + layout.start_at;
        let race = |raw: f32| (raw - start).rem_euclid(length);
        let (up_raw, low_raw, cross_point, up_dir, low_dir) =
            plan.crossing(layout.bridge_edge).ok_or_else(|| other("the bridge straight crosses nothing".into()))?;
        let mut bumps = vec![(up_raw, BRIDGE_HEIGHT, 35.0, 185.0)];
        bumps.extend(layout.crests.iter().map(|&(seg, frac, h, top, ramp)| (plan.at_segment(seg, frac), h, top, ramp)));
        let profile = Profile { bumps, length };
        let n = (length / SAMPLE_STEP).round() as usize;
        let step = length / n as f32;
        let raw: Vec<(Vec2, Vec2, f32)> = (0..n).map(|i| plan.eval(start + i as f32 * step)).collect();
        let upper_s = race(up_raw);
        let lower_s = race(low_raw);
        let bases = base_levels(layout, &plan, start, n, step);
        let mut samples = Vec::with_capacity(n);
        for (i, &(pos, dir, kappa_raw)) in raw.iter().enumerate() {
            let s = i as f32 * step;
            let kappa = (0..11).map(|j| raw[(i + n + j - 5) % n].2).sum::<f32>() / 11.0;
            // No banking where the roads cross.
            let calm = smoothstep(60.0, 100.0, loop_dist(s, upper_s, length))
                * smoothstep(40.0, 80.0, loop_dist(s, lower_s, length));
            let bank = (kappa * 24.0).clamp(-0.18, 0.18) * calm;
            let levels = (profile.height(start + s), bases[i]);
            samples.push(Sample::new(layout, s, (pos, dir), (kappa, kappa_raw), levels, bank));
        }
        let upper_i = (upper_s / step).round() as usize % n;
        let lower_i = (lower_s / step).round() as usize % n;
        // The open span must clear the lower road's barriers (with room for the piers) and the abutments'
        // feet; the piers stand just outside the lower road's barriers.
        let (sin_a, cos_a) = (cross2(up_dir, low_dir).abs().max(0.2), up_dir.dot(low_dir).abs());
        let lower_bo = samples[lower_i].bo[0].max(samples[lower_i].bo[1]);
        let pier_offset = (lower_bo + 2.0 + 6.0 * cos_a) / sin_a;
        let abutment = (lower_bo + 5.0 + (BARRIER_OFFSET_RAISED + 2.5) * cos_a) / sin_a;
        let span = (abutment / step).ceil() as usize;
        let apex = (0..layout.corners.len()).map(|k| race(plan.at_segment(2 * k + 1, 0.5))).collect();
        let tile = |t: f32| length / (length / t).round();
        let viaduct = layout.relief.map_or((0.0, 0.0), |r| {
            let (seg, f0, f1) = r.viaduct;
            (race(plan.at_segment(seg, f0)), race(plan.at_segment(seg, f1)))
        });
        let mut c = Circuit {
            layout,
            length,
            step,
            samples,
            upper_s,
            lower_s,
            cross_point,
            upper_i,
            span,
            pier_offset,
            viaduct,
            apex,
            road_tile: tile(12.0),
            kerb_tile: tile(3.0),
            barrier_tile: tile(4.0),
            apron: vec![],
            widths: vec![],
        };
        c.widths = (0..c.n()).map(|i| [c.reach(i, 0), c.reach(i, 1)]).collect();
        c.apron = (0..c.n()).map(|i| [0, 1].map(|side| c.apron_extent(i, side))).collect();
        Ok(c)
    }

    /// Half-width of the corridor kept free of ground on one side of sample `i`: to the barrier line, or to
    /// the embankment's foot.
    pub(super) fn reach(&self, i: usize, side: usize) -> f32 {
        let y = self.samples[i].verge(side).y - self.samples[i].base;
        self.samples[i].bo[side] + if y > 0.15 { self.foot(i, y) } else { 0.0 }
    }

    /// Whether no ground may lie within the corridor of sample `i` (everything but the open spans).
    pub(super) fn on_ground(&self, i: usize) -> bool {
        !self.open(i)
    }

    /// Whether sample `i` is on the viaduct's open span.
    pub(super) fn in_viaduct(&self, i: usize) -> bool {
        (self.viaduct.0..self.viaduct.1).contains(&self.samples[i].s)
    }

    /// Whether sample `i` is carried by a deck with nothing under it (the bridge's span or the viaduct).
    pub(super) fn open(&self, i: usize) -> bool {
        self.in_span(i) || self.in_viaduct(i)
    }

    /// The corridor around sample `j` as a plan rectangle, grown by `margin`: centre, ahead and right unit
    /// vectors, range along (symmetric) and range across (left, right). The corridor is the union of these.
    fn slab(&self, j: usize, margin: f32) -> (Vec2, Vec2, Vec2, f32, [f32; 2]) {
        let t = &self.samples[j];
        let across = [-(self.widths[j][0] + margin), self.widths[j][1] + margin];
        (
            Vec2::new(t.p.x, t.p.z),
            Vec2::new(t.fwd.x, t.fwd.z),
            Vec2::new(t.right.x, t.right.z),
            self.step * 0.5 + 0.5,
            across,
        )
    }

    /// How far the apron of sample `i` may reach: up to [`APRON`] beyond the corridor, stopping short of any
    /// other part of the track (the bridge ramps excepted: ground under them is hidden by the embankment).
    fn apron_extent(&self, i: usize, side: usize) -> f32 {
        let s = &self.samples[i];
        let start = self.reach(i, side);
        let origin = Vec2::new(s.p.x, s.p.z);
        let out = Vec2::new(s.right.x, s.right.z) * SIDE[side];
        let clear = |x: f32| {
            let q = origin + out * x;
            (0..self.n()).all(|j| {
                if !self.on_ground(j) || (self.bridge_zone(j) && self.samples[j].h > 0.5) {
                    return true;
                }
                let (p, fwd, right, along, across) = self.slab(j, 1.0);
                let (a, l) = ((q - p).dot(fwd), (q - p).dot(right));
                a.abs() >= along || l <= across[0] || l >= across[1]
            })
        };
        // On the inside of a corner the apron stops at the centre of the arc (beyond it would fold over).
        let limit = if s.kappa_raw * SIDE[side] < 0.0 { 1.0 / s.kappa_raw.abs() } else { f32::INFINITY };
        let cap = (start + APRON).min(limit);
        let mut a = start;
        while a < cap {
            let next = (a + 2.0).min(cap);
            if !clear(next) {
                break;
            }
            a = next;
        }
        a
    }

    /// Whether a plan rectangle overlaps the corridor (grown by 3 m) of any sample on the ground (separating
    /// axis test against each sample's rectangle).
    pub(super) fn touches(&self, lo: Vec2, hi: Vec2) -> bool {
        let rect = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
        let range = |pts: &[Vec2], axis: Vec2, origin: Vec2| {
            pts.iter()
                .map(|q| (*q - origin).dot(axis))
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
        };
        (0..self.n()).any(|j| {
            if !self.on_ground(j) {
                return false;
            }
            let (p, fwd, right, along, across) = self.slab(j, 3.0);
            let corners = [(-along, across[0]), (along, across[0]), (along, across[1]), (-along, across[1])]
                .map(|(a, l)| p + fwd * a + right * l);
            let (f0, f1) = range(&rect, fwd, p);
            let (r0, r1) = range(&rect, right, p);
            let (x0, x1) = range(&corners, Vec2::X, Vec2::ZERO);
            let (z0, z1) = range(&corners, Vec2::Y, Vec2::ZERO);
            f1 > -along
                && f0 < along
                && r1 > across[0]
                && r0 < across[1]
                && x1 > lo.x
                && x0 < hi.x
                && z1 > lo.y
                && z0 < hi.y
        })
    }

    pub(super) fn n(&self) -> usize {
        self.samples.len()
    }

    /// Index distance between two samples around the loop.
    fn index_dist(&self, a: usize, b: usize) -> usize {
        let d = (a + self.n() - b) % self.n();
        d.min(self.n() - d)
    }

    /// Whether sample `i` is over the open span of the bridge (no embankment under it).
    pub(super) fn in_span(&self, i: usize) -> bool {
        self.index_dist(i, self.upper_i) <= self.span
    }

    /// Whether sample `i` is on the bridge's ramps (steep concrete sides, parapets).
    pub(super) fn bridge_zone(&self, i: usize) -> bool {
        loop_dist(self.samples[i].s, self.upper_s, self.length) < 240.0
    }

    /// Whether sample `i` has kerbs.
    pub(super) fn kerb(&self, i: usize) -> bool {
        self.samples[i].kappa.abs() > 1.0 / 260.0
    }

    /// Horizontal reach of the embankment side beyond the barrier at sample `i`, for a verge `height` up.
    pub(super) fn foot(&self, i: usize, height: f32) -> f32 {
        if self.bridge_zone(i) { 0.2 * height + 0.3 } else { 1.5 * height + 0.3 }
    }

    /// Whether the road mesh needs every sample around `i` (tight corners, the crossing).
    fn fine(&self, i: usize) -> bool {
        let lower_i = (self.lower_s / self.step).round() as usize % self.n();
        self.samples[i].kappa_raw.abs() > 1.0 / 90.0
            || self.index_dist(i, self.upper_i) <= self.span + 6
            || self.index_dist(i, lower_i) <= 8
    }

    /// The samples the road mesh uses, in order.
    pub(super) fn road_indices(&self) -> Vec<usize> {
        let n = self.n();
        let mut idx = vec![0];
        let mut i = 0;
        while i < n {
            i += if self.fine(i) || self.fine((i + 1) % n) { 1 } else { 2 };
            if i < n {
                idx.push(i);
            }
        }
        idx
    }

    /// The frame at distance `s` from the start line (interpolated between samples).
    pub(super) fn at(&self, s: f32) -> Frame {
        let x = s.rem_euclid(self.length) / self.step;
        let i = (x.floor() as usize).min(self.n() - 1);
        let t = x - i as f32;
        let (a, b) = (&self.samples[i], &self.samples[(i + 1) % self.n()]);
        Frame {
            p: a.p.lerp(b.p, t),
            fwd: a.fwd.lerp(b.fwd, t).normalize_or_zero(),
            right: a.right.lerp(b.right, t).normalize_or_zero(),
            lat: a.lat.lerp(b.lat, t).normalize_or_zero(),
        }
    }

    /// Plan distance from `p` (x, z) to the nearest centreline sample.
    pub(super) fn distance(&self, p: Vec2) -> f32 {
        self.samples.iter().map(|s| Vec2::new(s.p.x, s.p.z).distance_squared(p)).fold(f32::INFINITY, f32::min).sqrt()
    }

    /// Plan bounds of the centreline.
    pub(super) fn bounds(&self) -> (Vec2, Vec2) {
        let mut lo = Vec2::splat(f32::INFINITY);
        let mut hi = Vec2::splat(f32::NEG_INFINITY);
        for s in &self.samples {
            lo = lo.min(Vec2::new(s.p.x, s.p.z));
            hi = hi.max(Vec2::new(s.p.x, s.p.z));
        }
        (lo, hi)
    }
}
