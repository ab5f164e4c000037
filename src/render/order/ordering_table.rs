//! The ordering table (seed 000, Sega EP 0 670 560): depth buckets of linked polygon lists.
//!
//! Each polygon is registered, in submission order, into the bucket of its representative depth. A bucket is a
//! linked list with a start and an end entry; registering appends to the end (or, for near-to-far drawing,
//! prepends to the start), so no sorting happens inside a bucket. When every polygon is registered the buckets
//! are chained into one list by linking each non-empty bucket's end to the next non-empty bucket's start,
//! far to near (claim 4) or near to far (claim 5). Drawing near to far reverses the order inside each bucket
//! too, so it is exactly the reverse of the far-to-near list, as the patent's paragraph 88 allows.
//!
//! A frame's renderer does not follow the links: [`OrderingTable::sort`] gives the order the links would,
//! as a counting sort of the buckets (each bucket's entries stay in submission order). Walking the links is
//! one dependent load at a random place per polygon; counting, placing the buckets and writing each entry at
//! its bucket's next slot are passes over arrays. The linked table stays as the reference a test holds the
//! sort to. The sort runs on one thread: split across threads by bucket ranges, each thread would scan every
//! entry for its own, and that scan's branch on the range goes one way or the other at random, which costs
//! more than the split saves.

/// Direction in which the buckets are chained.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Direction {
    /// Farthest bucket first: painter's order (`bucket-far`).
    #[default]
    FarToNear,
    /// Nearest bucket first, drawn with 'already drawn' coverage (`bucket-near`).
    NearToFar,
}

use crate::render::core::options::BucketMapping;

const NONE: u32 = u32::MAX;

/// A depth-bucket ordering table, reused from frame to frame without reallocating.
#[derive(Clone, Debug, Default)]
pub struct OrderingTable {
    start: Vec<u32>,
    end: Vec<u32>,
    next: Vec<u32>,
    head: u32,
    near: f32,
    scale: f32,
    mapping: BucketMapping,
    direction: Direction,
    /// Entries per bucket, nearest first.
    counts: Vec<u32>,
    /// [`OrderingTable::sort`]'s scratch: each entry's place among the buckets in far-to-near order, and
    /// each place's next slot in the order.
    places: Vec<u32>,
    next_slot: Vec<u32>,
}

impl OrderingTable {
    /// An empty table; call [`OrderingTable::reset`] before registering.
    #[must_use]
    pub fn new() -> Self {
        Self { head: NONE, ..Self::default() }
    }

    /// Empties the table and sets `buckets` buckets (at least one) spanning depths `near..=far`.
    ///
    /// With [`BucketMapping::Reciprocal`] a `near` that is not positive falls back to linear buckets, since
    /// `1/z` has no meaning there.
    pub fn reset(&mut self, buckets: usize, mapping: BucketMapping, near: f32, far: f32, direction: Direction) {
        let buckets = buckets.max(1);
        self.start.clear();
        self.start.resize(buckets, NONE);
        self.end.clear();
        self.end.resize(buckets, NONE);
        self.counts.clear();
        self.counts.resize(buckets, 0);
        self.next.clear();
        self.head = NONE;
        self.direction = direction;
        let usable_reciprocal = mapping == BucketMapping::Reciprocal && near > 0.0 && far > near;
        self.mapping = if usable_reciprocal { BucketMapping::Reciprocal } else { BucketMapping::Linear };
        if usable_reciprocal {
            self.near = 1.0 / near;
            let span = 1.0 / near - 1.0 / far;
            self.scale = buckets as f32 / span;
        } else {
            self.near = near;
            let span = far - near;
            self.scale = if span > 0.0 && span.is_finite() { buckets as f32 / span } else { 0.0 };
        }
    }

    /// Number of buckets.
    #[must_use]
    pub fn buckets(&self) -> usize {
        self.start.len()
    }

    /// The bucket (0 = nearest) a representative depth falls into; out-of-range and NaN depths are clamped.
    #[must_use]
    pub fn bucket_of(&self, depth: f32) -> usize {
        let f = match self.mapping {
            BucketMapping::Linear => (depth - self.near) * self.scale,
            BucketMapping::Reciprocal => (self.near - 1.0 / depth) * self.scale,
        };
        // `as usize` truncates and saturates: negative and NaN become 0, so for every `f` it gives what
        // `f.floor() as usize` would, without the call to libm's `floorf` (the x86-64 baseline has no
        // rounding instruction, so `floor` would be a call per polygon registered).
        (f as usize).min(self.start.len().saturating_sub(1))
    }

    /// Registers the next polygon (its entry number is the count registered before it) at `depth`.
    pub fn register(&mut self, depth: f32) -> u32 {
        let entry = self.next.len() as u32;
        self.next.push(NONE);
        let b = self.bucket_of(depth);
        self.counts[b] += 1;
        if self.start[b] == NONE {
            self.start[b] = entry;
            self.end[b] = entry;
        } else if self.direction == Direction::FarToNear {
            let last = self.end[b] as usize;
            self.next[last] = entry;
            self.end[b] = entry;
        } else {
            self.next[entry as usize] = self.start[b];
            self.start[b] = entry;
        }
        entry
    }

    /// Links the buckets into one list in the table's direction.
    pub fn chain(&mut self) {
        let n = self.start.len();
        let mut prev_end = NONE;
        self.head = NONE;
        for i in 0..n {
            let b = if self.direction == Direction::FarToNear { n - 1 - i } else { i };
            if self.start[b] == NONE {
                continue;
            }
            if prev_end == NONE {
                self.head = self.start[b];
            } else {
                self.next[prev_end as usize] = self.start[b];
            }
            prev_end = self.end[b];
        }
    }

    /// Entry numbers in drawing order (valid after [`OrderingTable::chain`]).
    pub fn iter(&self) -> impl Iterator<Item = u32> + '_ {
        let mut cur = self.head;
        let mut left = self.next.len();
        std::iter::from_fn(move || {
            if cur == NONE || left == 0 {
                return None;
            }
            left -= 1;
            let e = cur;
            cur = self.next[e as usize];
            Some(e)
        })
    }

    /// How many entries each bucket holds (nearest first), for occupancy statistics.
    #[must_use]
    pub fn occupancy(&self) -> Vec<u32> {
        self.counts.clone()
    }

    /// Writes into `order` the entry numbers (entry `i` at `depths[i]`) in the order that registering
    /// `depths` into this freshly reset table, chaining ([`OrderingTable::chain`]) and iterating
    /// ([`OrderingTable::iter`]) would give, as a counting sort. Only the bucket counts are kept (for
    /// [`OrderingTable::occupancy`]); no links are built, so use either this or `register`, not both.
    pub fn sort(&mut self, depths: &[f32], order: &mut Vec<u32>) {
        debug_assert!(self.next.is_empty(), "sort on a table with registered entries");
        let (n, buckets) = (depths.len(), self.start.len());
        order.clear();
        if buckets == 0 {
            // Never reset: one bucket, as `reset` would make at least.
            order.extend(0..n as u32);
        } else {
            order.resize(n, 0);
            // Each entry's place: its bucket counted from the far end; then where each place begins.
            let mut places = std::mem::take(&mut self.places);
            places.clear();
            places.extend(depths.iter().map(|&d| (buckets - 1 - self.bucket_of(d)) as u32));
            let mut next = std::mem::take(&mut self.next_slot);
            next.clear();
            next.resize(buckets, 0);
            for &p in &places {
                next[p as usize] += 1;
            }
            let mut first = 0;
            for (place, slot) in next.iter_mut().enumerate() {
                let c = *slot;
                self.counts[buckets - 1 - place] = c;
                *slot = first;
                first += c;
            }
            // Entries in submission order, each at its place's next slot.
            for (entry, &p) in places.iter().enumerate() {
                let slot = &mut next[p as usize];
                if let Some(o) = order.get_mut(*slot as usize) {
                    *o = entry as u32;
                }
                *slot += 1;
            }
            self.places = places;
            self.next_slot = next;
        }
        // Near to far is exactly the far-to-near list reversed.
        if self.direction == Direction::NearToFar {
            order.reverse();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fig. 5 of the seed: polygon number and distance along Z1; Fig. 4: five groups of width 1 from 0 to 5.
    const FIG5: [(u32, f32); 10] =
        [(1, 0.5), (2, 2.3), (3, 0.8), (4, 1.1), (5, 4.2), (6, 3.3), (7, 3.5), (8, 4.9), (9, 1.4), (10, 0.3)];

    fn order(direction: Direction) -> Vec<u32> {
        let mut ot = OrderingTable::new();
        ot.reset(5, BucketMapping::Linear, 0.0, 5.0, direction);
        for (_, d) in FIG5 {
            ot.register(d);
        }
        ot.chain();
        ot.iter().map(|e| FIG5[e as usize].0).collect()
    }

    #[test]
    fn sega_worked_example_far_to_near() {
        assert_eq!(order(Direction::FarToNear), [5, 8, 6, 7, 2, 4, 9, 1, 3, 10]);
    }

    #[test]
    fn sega_worked_example_near_to_far() {
        assert_eq!(order(Direction::NearToFar), [10, 3, 1, 9, 4, 2, 7, 6, 8, 5]);
    }

    #[test]
    fn buckets_are_the_floor_of_the_mapped_depth_for_any_depth() {
        let mut ot = OrderingTable::new();
        let mut seed = 0x2545_f491u32;
        let mut depths = vec![f32::NAN, f32::INFINITY, -f32::INFINITY, 0.0, -0.0, 1e-40, -1e-40, 3e38, -3e38];
        for _ in 0..20_000 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            depths.push((seed as i32) as f32 / 1e6);
            depths.push(f32::from_bits(seed));
        }
        for (mapping, near, far, buckets) in [
            (BucketMapping::Linear, 1.0, 50.0, 256),
            (BucketMapping::Reciprocal, 0.5, 900.0, 1024),
            (BucketMapping::Linear, -3.0, 7.5, 7),
        ] {
            ot.reset(buckets, mapping, near, far, Direction::FarToNear);
            for &d in &depths {
                let f = match ot.mapping {
                    BucketMapping::Linear => (d - ot.near) * ot.scale,
                    BucketMapping::Reciprocal => (ot.near - 1.0 / d) * ot.scale,
                };
                let reference = (f.floor() as usize).min(buckets - 1);
                assert_eq!(ot.bucket_of(d), reference, "{mapping:?} depth {d}");
            }
        }
    }

    #[test]
    fn sega_groups_match_fig4() {
        let mut ot = OrderingTable::new();
        ot.reset(5, BucketMapping::Linear, 0.0, 5.0, Direction::FarToNear);
        let groups: Vec<usize> = FIG5.iter().map(|&(_, d)| ot.bucket_of(d)).collect();
        assert_eq!(groups, [0, 2, 0, 1, 4, 3, 3, 4, 1, 0]);
        for (_, d) in FIG5 {
            ot.register(d);
        }
        assert_eq!(ot.occupancy(), [3, 2, 1, 2, 2]);
    }

    #[test]
    fn reciprocal_buckets_are_finer_near_the_eye_and_clamp() {
        let mut ot = OrderingTable::new();
        ot.reset(4, BucketMapping::Reciprocal, 1.0, 100.0, Direction::FarToNear);
        assert_eq!(ot.bucket_of(1.0), 0);
        assert_eq!(ot.bucket_of(1.3), 0);
        assert_eq!(ot.bucket_of(1.4), 1);
        assert_eq!(ot.bucket_of(50.0), 3);
        assert_eq!(ot.bucket_of(f32::NAN), 0);
        assert_eq!(ot.bucket_of(1e30), 3);
        assert_eq!(ot.bucket_of(-5.0), 3);
        // A non-positive near falls back to linear buckets.
        ot.reset(4, BucketMapping::Reciprocal, 0.0, 4.0, Direction::FarToNear);
        assert_eq!(ot.bucket_of(1.5), 1);
    }

    #[test]
    fn the_counting_sort_gives_the_linked_order() {
        let mut rng = crate::render::core::test_rng::Lcg(11);
        let hostile = [f32::NAN, f32::INFINITY, -f32::INFINITY, -1e30, 1e30, 0.0];
        let mut compared = 0;
        let mut table = OrderingTable::new();
        for case in 0..60 {
            let n = [0, 1, 2, 7, 100, 3000][case % 6];
            let buckets = [1, 3, 64, 1024, 5000][case % 5];
            let mapping = if case % 3 == 0 { BucketMapping::Reciprocal } else { BucketMapping::Linear };
            let depths: Vec<f32> = (0..n)
                .map(|_| {
                    // Few distinct depths in some cases, so buckets hold long runs.
                    if rng.below(20) == 0 {
                        hostile[rng.below(6) as usize]
                    } else {
                        rng.range(1, 2 + case as i32) as f32
                    }
                })
                .collect();
            for direction in [Direction::FarToNear, Direction::NearToFar] {
                let mut linked = OrderingTable::new();
                linked.reset(buckets, mapping, 1.0, 40.0, direction);
                for &d in &depths {
                    linked.register(d);
                }
                linked.chain();
                let expected: Vec<u32> = linked.iter().collect();
                // A reused table, as the renderer's is.
                for _ in 0..2 {
                    table.reset(buckets, mapping, 1.0, 40.0, direction);
                    let mut order = vec![99];
                    table.sort(&depths, &mut order);
                    assert_eq!(order, expected, "case {case}, {direction:?}");
                    assert_eq!(table.occupancy(), linked.occupancy(), "case {case}");
                    compared += order.len();
                }
            }
        }
        assert!(compared > 20_000);
    }

    #[test]
    fn empty_and_single_bucket_tables() {
        let mut ot = OrderingTable::new();
        ot.reset(0, BucketMapping::Linear, 3.0, 3.0, Direction::NearToFar);
        ot.chain();
        assert_eq!(ot.iter().count(), 0);
        for d in [5.0, 1.0, 3.0] {
            ot.register(d);
        }
        ot.chain();
        assert_eq!(ot.iter().collect::<Vec<_>>(), [2, 1, 0]);
    }
}
