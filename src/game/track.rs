//! The circuit as the simulation sees it: a closed centre line with width and banking, sampled every few
//! metres, and the queries the cars need (where am I along the lap, how far from the centre, how high).

use glam::{Vec2, Vec3};
use thiserror::Error;

/// Why a centre line could not be read.
#[derive(Debug, Error)]
pub enum TrackError {
    /// The text is not JSON.
    #[error("centre line: {0}")]
    Json(#[source] serde_json::Error),
    /// The JSON has no `samples` array.
    #[error("centre line: no samples")]
    NoSamples,
    /// Too few samples to make a circuit.
    #[error("centre line: {found} samples, need at least {MIN_SAMPLES}")]
    TooFewSamples {
        /// Samples in the file.
        found: usize,
    },
    /// One sample cannot be used.
    #[error("centre line: sample {index}: {problem}")]
    Sample {
        /// Its index in driving order (0 is on the start line).
        index: usize,
        /// What is wrong with it.
        problem: SampleProblem,
    },
    /// The lap is too short for the starting grid.
    #[error("centre line: a lap of {length:.0} m, need at least {MIN_LAP_M} m")]
    TooShort {
        /// The lap length in metres.
        length: f32,
    },
}

/// What is wrong with one sample of a centre line.
#[derive(Debug, Error, PartialEq)]
pub enum SampleProblem {
    /// The sample lacks its position, banking or width.
    #[error("lacks p, bank or width")]
    MissingFields,
    /// The position is not three numbers.
    #[error("has a bad position")]
    BadPosition,
    /// A number is NaN or infinite.
    #[error("a number is not finite")]
    NotFinite,
    /// A coordinate, the width or a barrier distance is beyond [`MAX_COORDINATE_M`].
    #[error("{value:e} is beyond the 1e6 m bound on coordinates and distances")]
    TooFar {
        /// The number.
        value: f32,
    },
    /// The road has no width.
    #[error("width {width} m is not positive")]
    NoWidth {
        /// The width.
        width: f32,
    },
    /// A barrier is on the road.
    #[error("a barrier at {barrier} m is inside the road's half width {half} m")]
    BarrierOnRoad {
        /// The barrier's distance from the centre line.
        barrier: f32,
        /// Half the road's width.
        half: f32,
    },
    /// The next sample is (nearly) at the same place seen from above.
    #[error("too close to sample {next} ({distance} m apart, need at least {MIN_SPACING_M} m)")]
    TooClose {
        /// The next sample's index (0 after the last).
        next: usize,
        /// Their horizontal distance in metres.
        distance: f32,
    },
}

/// Fewest samples a centre line may have.
pub const MIN_SAMPLES: usize = 8;
/// Largest coordinate, width or barrier distance accepted (metres): far beyond any circuit, small enough
/// that squared distances stay finite and precise in `f32`.
pub const MAX_COORDINATE_M: f32 = 1e6;
/// Closest two consecutive samples may be (metres, seen from above): closer, the segment has no direction.
pub const MIN_SPACING_M: f32 = 0.1;
/// Shortest lap accepted (metres): the grid of eight cars takes 64 m behind the line.
pub const MIN_LAP_M: f32 = 200.0;

/// One sample of the centre line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Position of the road centre (metres, Y up).
    pub pos: Vec3,
    /// Roll of the road surface in radians (positive raises the right side).
    pub bank: f32,
    /// Road width in metres.
    pub width: f32,
    /// Distance from the centre line to the barriers, left and right (metres).
    pub barrier: [f32; 2],
    /// Distance along the lap from the start line to this sample.
    pub s: f32,
}

/// Where a point is relative to the track.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Location {
    /// Index of the segment (from sample `index` to `index + 1`).
    pub index: usize,
    /// Distance along the lap.
    pub s: f32,
    /// Signed distance from the centre line, positive to the right of the driving direction.
    pub lateral: f32,
    /// Height of the road surface under the point.
    pub height: f32,
    /// Road width here.
    pub width: f32,
    /// Barrier distances from the centre line here, left and right.
    pub barrier: [f32; 2],
}

/// A closed circuit centre line.
#[derive(Clone, Debug, PartialEq)]
pub struct Track {
    samples: Vec<Sample>,
    length: f32,
}

/// How many segments either side of the hint [`Track::locate`] searches: enough for a car at top speed over
/// many ticks, few enough that the two levels of a crossing (far apart along the lap) never get confused.
const SEARCH: usize = 12;

impl Track {
    /// Builds a track from samples in driving order (the last joins back to the first): position, bank and
    /// width, with barriers 4 m beyond each road edge.
    pub fn new(points: &[(Vec3, f32, f32)]) -> Result<Self, TrackError> {
        let with_barriers: Vec<_> = points.iter().map(|&(p, b, w)| (p, b, w, [0.5 * w + 4.0; 2])).collect();
        Self::with_barriers(&with_barriers)
    }

    /// Builds a track from samples with their barrier distances (left, right); refuses a degenerate one
    /// (too few samples, a number not finite or beyond [`MAX_COORDINATE_M`], no width, a barrier on the
    /// road, consecutive samples closer than [`MIN_SPACING_M`], a lap shorter than [`MIN_LAP_M`]), naming
    /// the sample.
    pub fn with_barriers(points: &[(Vec3, f32, f32, [f32; 2])]) -> Result<Self, TrackError> {
        if points.len() < MIN_SAMPLES {
            return Err(TrackError::TooFewSamples { found: points.len() });
        }
        for (index, point) in points.iter().enumerate() {
            let next = (index + 1) % points.len();
            check_sample(point, points[next].0, next).map_err(|problem| TrackError::Sample { index, problem })?;
        }
        let mut s = 0.0;
        let mut samples = Vec::with_capacity(points.len());
        for (i, &(pos, bank, width, barrier)) in points.iter().enumerate() {
            samples.push(Sample { pos, bank, width, barrier, s });
            let next = points[(i + 1) % points.len()].0;
            s += flat(next - pos).length();
        }
        if s < MIN_LAP_M {
            return Err(TrackError::TooShort { length: s });
        }
        Ok(Self { samples, length: s })
    }

    /// Reads `centerline.json` as written by the asset generator.
    pub fn from_json(text: &str) -> Result<Self, TrackError> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(TrackError::Json)?;
        let arr = v.get("samples").and_then(|s| s.as_array()).ok_or(TrackError::NoSamples)?;
        let num = |x: Option<&serde_json::Value>| x.and_then(serde_json::Value::as_f64).map(|f| f as f32);
        let mut pts = Vec::with_capacity(arr.len());
        for (i, s) in arr.iter().enumerate() {
            let p = s.get("p").and_then(|p| p.as_array()).filter(|p| p.len() == 3);
            let (Some(p), Some(bank), Some(width)) = (p, num(s.get("bank")), num(s.get("width"))) else {
                return Err(TrackError::Sample { index: i, problem: SampleProblem::MissingFields });
            };
            let (Some(x), Some(y), Some(z)) = (num(p.first()), num(p.get(1)), num(p.get(2))) else {
                return Err(TrackError::Sample { index: i, problem: SampleProblem::BadPosition });
            };
            let barrier = match s.get("barrier").and_then(|b| b.as_array()) {
                Some(b) => [num(b.first()).unwrap_or(0.0), num(b.get(1)).unwrap_or(0.0)],
                None => [0.5 * width + 4.0; 2],
            };
            pts.push((Vec3::new(x, y, z), bank, width, barrier));
        }
        Self::with_barriers(&pts)
    }

    /// Lap length in metres.
    #[must_use]
    pub fn length(&self) -> f32 {
        self.length
    }

    /// The samples.
    #[must_use]
    pub fn samples(&self) -> &[Sample] {
        &self.samples
    }

    fn segment(&self, i: usize) -> (Sample, Sample) {
        let n = self.samples.len();
        (self.samples[i % n], self.samples[(i + 1) % n])
    }

    /// Locates a point (x, z) near the segment `hint`: the nearest segment within a window around it.
    #[must_use]
    pub fn locate(&self, p: Vec2, hint: usize) -> Location {
        let n = self.samples.len();
        let mut best: Option<(f32, Location)> = None;
        for k in 0..=2 * SEARCH {
            let i = (hint % n + n + k - SEARCH) % n;
            let (a, b) = self.segment(i);
            let (a2, b2) = (flat(a.pos), flat(b.pos));
            let d = b2 - a2;
            let len2 = d.length_squared().max(1e-6);
            let t = ((p - a2).dot(d) / len2).clamp(0.0, 1.0);
            let foot = a2 + d * t;
            let dist2 = (p - foot).length_squared();
            if best.as_ref().is_some_and(|(b, _)| *b <= dist2) {
                continue;
            }
            let dir = d / len2.sqrt();
            // Right of the driving direction (x, z) is (-dz, dx) with Y up... (dir.y is z): right = (-dir.y, dir.x).
            let right = Vec2::new(-dir.y, dir.x);
            let lateral = (p - foot).dot(right);
            let bank = a.bank + (b.bank - a.bank) * t;
            let centre_h = a.pos.y + (b.pos.y - a.pos.y) * t;
            let seg_len = len2.sqrt();
            let s = (a.s + seg_len * t) % self.length;
            best = Some((
                dist2,
                Location {
                    index: i,
                    s,
                    lateral,
                    height: centre_h + lateral * libm::sinf(bank),
                    width: a.width + (b.width - a.width) * t,
                    barrier: [a.barrier[0].min(b.barrier[0]), a.barrier[1].min(b.barrier[1])],
                },
            ));
        }
        let s0 = self.samples[0];
        best.map_or(
            Location { index: 0, s: 0.0, lateral: 0.0, height: s0.pos.y, width: s0.width, barrier: s0.barrier },
            |(_, l)| l,
        )
    }

    /// The segment index that contains lap distance `s`.
    #[must_use]
    pub fn index_at(&self, s: f32) -> usize {
        let s = s.rem_euclid(self.length);
        self.samples.partition_point(|x| x.s <= s).saturating_sub(1)
    }

    /// Point on the road at lap distance `s`, `lateral` metres right of the centre, and the driving direction.
    #[must_use]
    pub fn point_at(&self, s: f32, lateral: f32) -> (Vec3, Vec2) {
        let i = self.index_at(s);
        let (a, b) = self.segment(i);
        let seg = flat(b.pos - a.pos);
        let len = seg.length().max(1e-6);
        let t = ((s.rem_euclid(self.length) - a.s) / len).clamp(0.0, 1.0);
        let dir = seg / len;
        let right = Vec2::new(-dir.y, dir.x);
        let c = a.pos + (b.pos - a.pos) * t;
        let bank = a.bank + (b.bank - a.bank) * t;
        (Vec3::new(c.x + right.x * lateral, c.y + lateral * libm::sinf(bank), c.z + right.y * lateral), dir)
    }

    /// Signed curvature (1/m, positive turning right) around lap distance `s`, over a 20 m chord.
    #[must_use]
    pub fn curvature_at(&self, s: f32) -> f32 {
        let (_, d0) = self.point_at(s - 10.0, 0.0);
        let (_, d1) = self.point_at(s + 10.0, 0.0);
        libm::asinf(d0.perp_dot(d1)) / 20.0
    }
}

/// Checks one sample (position, bank, width, barriers) and its distance to the next one, `next`.
fn check_sample(
    &(pos, bank, width, barrier): &(Vec3, f32, f32, [f32; 2]),
    next_pos: Vec3,
    next: usize,
) -> Result<(), SampleProblem> {
    let numbers = [pos.x, pos.y, pos.z, bank, width, barrier[0], barrier[1]];
    if !numbers.iter().all(|x| x.is_finite()) {
        return Err(SampleProblem::NotFinite);
    }
    if let Some(&value) =
        [pos.x, pos.y, pos.z, width, barrier[0], barrier[1]].iter().find(|x| x.abs() > MAX_COORDINATE_M)
    {
        return Err(SampleProblem::TooFar { value });
    }
    if width <= 0.0 {
        return Err(SampleProblem::NoWidth { width });
    }
    if let Some(&b) = barrier.iter().find(|&&b| b <= 0.5 * width) {
        return Err(SampleProblem::BarrierOnRoad { barrier: b, half: 0.5 * width });
    }
    let distance = flat(next_pos - pos).length();
    // A NaN distance (impossible after the checks above) is refused too.
    if distance.is_nan() || distance < MIN_SPACING_M {
        return Err(SampleProblem::TooClose { next, distance });
    }
    Ok(())
}

/// The horizontal part (x, z) of a position.
#[must_use]
pub fn flat(v: Vec3) -> Vec2 {
    Vec2::new(v.x, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A circle of radius 100 m driven counter-clockwise seen from above (turning left).
    pub(crate) fn circle() -> Track {
        let pts: Vec<(Vec3, f32, f32)> = (0..200)
            .map(|i| {
                let a = i as f32 / 200.0 * std::f32::consts::TAU;
                (Vec3::new(100.0 * libm::cosf(a), 0.0, -100.0 * libm::sinf(a)), 0.0, 12.0)
            })
            .collect();
        Track::new(&pts).unwrap()
    }

    #[test]
    fn locate_and_point_at_agree() {
        let t = circle();
        assert!((t.length() - 628.3).abs() < 0.5);
        for s in [0.0f32, 50.0, 313.0, 600.0] {
            for lat in [-5.0f32, 0.0, 4.0] {
                let (p, _) = t.point_at(s, lat);
                let loc = t.locate(flat(p), t.index_at(s));
                let ds = (loc.s - s).rem_euclid(t.length());
                assert!(ds.min(t.length() - ds) < 0.5, "{s} {lat}: {loc:?}");
                assert!((loc.lateral - lat).abs() < 0.1, "{s} {lat}: {loc:?}");
            }
        }
        // Counter-clockwise seen from above is a left turn: the outside (larger radius) is to the right.
        let (p, _) = t.point_at(0.0, 3.0);
        assert!(flat(p).length() > 100.0);
        assert!(t.curvature_at(100.0) < 0.0, "left turn has negative curvature");
        assert!((t.curvature_at(100.0).abs() - 0.01).abs() < 0.001);
    }

    #[test]
    fn bad_centre_lines_are_errors() {
        assert!(matches!(Track::from_json("{"), Err(TrackError::Json(_))));
        assert!(matches!(Track::from_json("{}"), Err(TrackError::NoSamples)));
        assert!(matches!(Track::from_json(r#"{"samples": []}"#), Err(TrackError::TooFewSamples { found: 0 })));
        let bad = Track::from_json(r#"{"samples": [{"p": [0, "up", 0], "bank": 0, "width": 12}]}"#).map(|_| ());
        assert_eq!(bad.unwrap_err().to_string(), "centre line: sample 0: has a bad position");
        let bad = Track::from_json(r#"{"samples": [{"p": [0, 0, 0], "width": 12}]}"#).map(|_| ());
        assert_eq!(bad.unwrap_err().to_string(), "centre line: sample 0: lacks p, bank or width");
        // The sample and its problem, from a centre line that is refused for one sample.
        let sample = |r: Result<Track, TrackError>| match r {
            Err(TrackError::Sample { index, problem }) => Some((index, problem)),
            _ => None,
        };
        let at = |index, problem| Some((index, problem));
        assert_eq!(sample(Track::new(&[(Vec3::splat(f32::NAN), 0.0, 12.0); 10])), at(0, SampleProblem::NotFinite));
        let ring = |r: f32| -> Vec<(Vec3, f32, f32)> {
            (0..100)
                .map(|i| i as f32 / 100.0 * std::f32::consts::TAU)
                .map(|a| (Vec3::new(r * libm::cosf(a), 0.0, r * libm::sinf(a)), 0.0, 12.0))
                .collect()
        };
        assert!(Track::new(&ring(100.0)).is_ok());
        // Eight identical points: no direction and no length.
        let same = [(Vec3::new(1.0, 2.0, 3.0), 0.0, 12.0); 8];
        assert_eq!(sample(Track::new(&same)), at(0, SampleProblem::TooClose { next: 1, distance: 0.0 }));
        let mut repeated = ring(100.0);
        repeated[42] = repeated[41];
        assert_eq!(sample(Track::new(&repeated)), at(41, SampleProblem::TooClose { next: 42, distance: 0.0 }));
        // The last sample closes the loop onto the first.
        let mut closed = ring(100.0);
        closed[99] = closed[0];
        assert_eq!(sample(Track::new(&closed)), at(99, SampleProblem::TooClose { next: 0, distance: 0.0 }));
        let mut huge = ring(100.0);
        huge[5].0.x = 1e30;
        assert_eq!(sample(Track::new(&huge)), at(5, SampleProblem::TooFar { value: 1e30 }));
        let mut flat_road = ring(100.0);
        flat_road[3].2 = 0.0;
        assert_eq!(sample(Track::new(&flat_road)), at(3, SampleProblem::NoWidth { width: 0.0 }));
        assert!(matches!(Track::new(&ring(20.0)), Err(TrackError::TooShort { length }) if length < MIN_LAP_M));
        let message = Track::new(&repeated).unwrap_err().to_string();
        assert_eq!(message, "centre line: sample 41: too close to sample 42 (0 m apart, need at least 0.1 m)");
    }
}

/// Test tracks shared by the game's unit tests.
#[cfg(test)]
pub(crate) mod tests_support {
    use super::*;

    /// An oval: 2 km straight along -Z from the origin, a 100 m radius turn, 2 km back, and a turn home.
    pub(crate) fn straight() -> Track {
        let mut pts = vec![];
        let mut push = |p: Vec3| pts.push((p, 0.0, 12.0));
        for i in 0..400 {
            push(Vec3::new(0.0, 0.0, -5.0 * i as f32));
        }
        for i in 0..60 {
            let a = i as f32 / 60.0 * std::f32::consts::PI;
            push(Vec3::new(100.0 - 100.0 * libm::cosf(a), 0.0, -2000.0 - 100.0 * libm::sinf(a)));
        }
        for i in 0..400 {
            push(Vec3::new(200.0, 0.0, -2000.0 + 5.0 * i as f32));
        }
        for i in 0..60 {
            let a = i as f32 / 60.0 * std::f32::consts::PI;
            push(Vec3::new(100.0 + 100.0 * libm::cosf(a), 0.0, 100.0 * libm::sinf(a)));
        }
        Track::new(&pts).unwrap_or_else(|e| panic!("{e}"))
    }
}
