//! Where the charts' labels go: each front point's label is put at the first of a list of places around
//! it where it overlaps no label already placed and no front point, so that labels of points drawn close
//! together (the cluster at the knee) stay readable.
//!
//! Greedy, in the order given (the chart gives the front from fast to slow): the first places tried sit
//! beside the point, the later ones further up and down (drawn with a leader line back to the point). A
//! label that fits nowhere is left out rather than drawn over another; the point keeps its ring.

/// A box in backend pixels (a label's, a point's ring, the plotting area): left, top, right, bottom (right
/// and bottom excluded).
pub type Box2 = (i32, i32, i32, i32);

/// How far the ring around a front point reaches, in pixels: labels keep clear of it.
const RING: i32 = 9;

/// Offsets of a label's top-left corner from its point, in the order they are tried (`w`: label width).
fn candidates(w: i32, h: i32) -> Vec<(i32, i32)> {
    let mut v = vec![(RING, -RING - h), (RING, RING - 2), (-RING - w, -RING - h), (-RING - w, RING - 2)];
    for step in 1..=8 {
        let d = step * (h + 2);
        v.extend([(RING, -RING - h - d), (RING, RING - 2 + d), (-RING - w, -RING - h - d), (-RING - w, RING - 2 + d)]);
    }
    v
}

/// The box a front point's ring keeps clear around `(x, y)`.
fn ring(x: i32, y: i32) -> Box2 {
    (x - RING, y - RING, x + RING, y + RING)
}

/// Whether two boxes overlap.
fn overlaps(a: Box2, b: Box2) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// The box of each label (`sizes`: width and height in pixels) of the points at `points`, kept inside
/// `area`; `None` for a label that fits nowhere.
#[must_use]
pub fn place(points: &[(i32, i32)], sizes: &[(u32, u32)], area: Box2) -> Vec<Option<Box2>> {
    let rings: Vec<Box2> = points.iter().map(|&(x, y)| ring(x, y)).collect();
    let mut placed: Vec<Box2> = vec![];
    let mut out = Vec::with_capacity(points.len());
    for (&(x, y), &(w, h)) in points.iter().zip(sizes) {
        let (w, h) = (i32::try_from(w).unwrap_or(i32::MAX / 4), i32::try_from(h).unwrap_or(i32::MAX / 4));
        let fits = |b: Box2| {
            b.0 >= area.0
                && b.1 >= area.1
                && b.2 <= area.2
                && b.3 <= area.3
                && !placed.iter().any(|&p| overlaps(p, b))
                && !rings.iter().any(|&r| overlaps(r, b))
        };
        let found =
            candidates(w, h).into_iter().map(|(dx, dy)| (x + dx, y + dy, x + dx + w, y + dy + h)).find(|&b| fits(b));
        if let Some(b) = found {
            placed.push(b);
        }
        out.push(found);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_of_close_points_do_not_overlap_each_other_or_the_points() {
        // Five points a few pixels apart, as at the chart's knee, and one alone.
        let points = [(100, 200), (104, 203), (110, 199), (116, 205), (121, 202), (400, 100)];
        let sizes = [(90, 14), (120, 14), (80, 14), (100, 14), (70, 14), (60, 14)];
        let area = (0, 0, 600, 400);
        let boxes = place(&points, &sizes, area);
        let got: Vec<Box2> = boxes.iter().map(|b| b.expect("room for every label")).collect();
        for (i, a) in got.iter().enumerate() {
            assert_eq!((a.2 - a.0, a.3 - a.1), (sizes[i].0 as i32, sizes[i].1 as i32));
            assert!(a.0 >= 0 && a.1 >= 0 && a.2 <= 600 && a.3 <= 400, "{a:?} inside");
            for b in &got[i + 1..] {
                assert!(!overlaps(*a, *b), "{a:?} and {b:?}");
            }
            for &(x, y) in &points {
                assert!(!overlaps(*a, ring(x, y)), "{a:?} covers ({x}, {y})");
            }
        }
        // The lone point's label sits at the first place: right of it, above.
        assert_eq!(got[5], (400 + RING, 100 - RING - 14, 400 + RING + 60, 100 - RING));
    }

    #[test]
    fn a_label_goes_below_its_point_when_there_is_no_room_above() {
        // A point near the top of the area: the label cannot go above it, so it takes the second place,
        // right of the point and below, beside it (no leader line needed).
        let boxes = place(&[(100, 12)], &[(60, 14)], (0, 0, 600, 400));
        assert_eq!(boxes, vec![Some((100 + RING, 12 + RING - 2, 100 + RING + 60, 12 + RING - 2 + 14))]);
    }

    #[test]
    fn a_label_with_no_room_is_left_out() {
        // The area is no bigger than the ring: nowhere to put a label.
        let boxes = place(&[(10, 10)], &[(50, 14)], (0, 0, 20, 20));
        assert_eq!(boxes, vec![None]);
        // Nothing to place: nothing placed.
        assert!(place(&[], &[], (0, 0, 100, 100)).is_empty());
    }
}
