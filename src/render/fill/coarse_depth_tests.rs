//! The coarse depth's floors, raised only under what a polygon covers whole, and a band's rest. (Frames
//! with and without it are compared in the integration tests, `coarse_depth`.)

use super::*;
use crate::render::core::fixed::Fx28_4;
use crate::render::core::vertex::ATTRS;

/// A screen polygon with corners at `xy` (pixels) and depth `z` at every corner.
fn polygon(xy: &[(f32, f32)], z: f32) -> Vec<ScreenVertex> {
    xy.iter()
        .map(|&(x, y)| {
            let mut attrs = [0.0; ATTRS];
            attrs[0] = z;
            ScreenVertex {
                x: Fx28_4::from_f32(x).expect("on the grid"),
                y: Fx28_4::from_f32(y).expect("on the grid"),
                attrs,
            }
        })
        .collect()
}

#[test]
fn floors_rise_only_under_what_a_polygon_covers_whole() {
    let mut c = CoarseDepth::default();
    let band = (100, 124);
    c.begin(80, 24);
    // A triangle over the band's left part: its right angle above and left of the band, the hypotenuse from
    // (70, 90) to (-10, 170).
    let tri = polygon(&[(-10.0, 90.0), (70.0, 90.0), (-10.0, 170.0)], 0.5);
    let (_, b) = reach(&tri, band, 80).expect("in the band");
    c.cover(&tri, band, &b);
    // Tiles of 16 x 8: the first row of tiles (rows 100-108) is covered to column 70 - 18 = 52 at its
    // bottom, less 1.5 pixels from the edge (2.1 columns): tiles 0-2 (columns 0-48). The second row
    // (108-116) to column 44 less as much: tiles 0-1. The third (116-124) to 36: tiles 0-1 (0-32).
    let raised: Vec<bool> = c.floor.iter().map(|&f| f > 0.0).collect();
    let expected =
        [[true, true, true, false, false], [true, true, false, false, false], [true, true, false, false, false]];
    assert_eq!(raised, expected.concat(), "floors {:?}", c.floor);
    assert!(c.floor[0] < 0.5 && c.floor[0] > 0.499, "floor {} not just under the depth", c.floor[0]);
    // Behind it, within the covered tiles: hidden; a hair nearer than its floor, or reaching a tile it does
    // not cover: not.
    let behind = polygon(&[(2.0, 102.0), (30.0, 103.0), (4.0, 120.0)], 0.4);
    let (z, b) = reach(&behind, band, 80).expect("in the band");
    assert!(c.hidden(&b, z));
    let (z, b) = reach(&polygon(&[(2.0, 102.0), (30.0, 103.0), (4.0, 120.0)], 0.49995), band, 80).expect("in");
    assert!(!c.hidden(&b, z), "within the margin");
    let (z, b) = reach(&polygon(&[(2.0, 102.0), (50.0, 103.0), (4.0, 120.0)], 0.4), band, 80).expect("in");
    assert!(!c.hidden(&b, z), "past the covered tiles");
    // A polygon whose depth varies is held an eighth of its range nearer: hidden at 0.3-0.45 (up to 0.469),
    // not at 0.1-0.48 (up to 0.528, though its corners are all behind the floor).
    let sloped = |near: f32, far: f32| {
        let mut p = polygon(&[(2.0, 102.0), (30.0, 103.0), (4.0, 120.0)], far);
        p[1].attrs[0] = near;
        reach(&p, band, 80).expect("in the band")
    };
    let ((z, b), (z2, b2)) = (sloped(0.45, 0.3), sloped(0.48, 0.1));
    assert!(c.hidden(&b, z) && !c.hidden(&b2, z2), "{z} {z2}");
    // A non-convex outline covers nothing.
    let mut d = CoarseDepth::default();
    d.begin(80, 24);
    let dart = polygon(&[(0.0, 90.0), (79.0, 90.0), (10.0, 110.0), (0.0, 130.0)], 0.5);
    let (_, b) = reach(&dart, band, 80).expect("in the band");
    d.cover(&dart, band, &b);
    // Nor does a polygon with a corner repeated, which would hide a turn from the convexity check.
    let doubled = polygon(&[(-10.0, 90.0), (90.0, 90.0), (90.0, 90.0), (90.0, 140.0), (-10.0, 140.0)], 0.5);
    let (_, b) = reach(&doubled, band, 80).expect("in the band");
    d.cover(&doubled, band, &b);
    assert!(d.floor.iter().all(|&f| f == f32::NEG_INFINITY), "{:?}", d.floor);
    let square = polygon(&[(-10.0, 90.0), (90.0, 90.0), (90.0, 140.0), (-10.0, 140.0)], 0.5);
    d.cover(&square, band, &reach(&square, band, 80).expect("in the band").1);
    assert!(d.floor.iter().all(|&f| f > 0.499), "{:?}", d.floor);
}

#[test]
fn a_band_that_hides_little_rests_and_is_tried_again() {
    let memory = AtomicU8::new(0);
    let mut coarse = CoarseDepth::default();
    let band = (0, 16);
    let far = polygon(&[(1.0, 1.0), (9.0, 1.0), (1.0, 9.0)], 0.1);
    let wall = polygon(&[(-10.0, -10.0), (74.0, -10.0), (74.0, 26.0), (-10.0, 26.0)], 0.5);
    // A frame where nothing covers a tile: every polygon tried, none hidden.
    let mut t = BandTest::begin(&mut coarse, Some(&memory), true, band, 64);
    for _ in 0..20 {
        assert!(t.rows(&far).is_some());
    }
    t.end();
    assert_eq!(memory.load(Ordering::Relaxed), REST);
    for rest in (0..REST).rev() {
        let mut t = BandTest::begin(&mut coarse, Some(&memory), true, band, 64);
        assert!(!t.on());
        t.cover_all([wall.as_slice()].into_iter());
        assert_eq!(t.rows(&far).map(|r| r.0), Some(band), "resting");
        t.end();
        assert_eq!(memory.load(Ordering::Relaxed), rest);
    }
    // Tried again: the wall's floors raised before anything is drawn hide the far polygon, whichever of
    // the two the bin holds first, never the wall itself; the band keeps on.
    let mut t = BandTest::begin(&mut coarse, Some(&memory), true, band, 64);
    t.cover_all([wall.as_slice()].into_iter());
    assert_eq!(t.rows(&far).map(|r| r.0), None);
    assert_eq!(t.rows(&wall).map(|r| r.0), Some(band));
    t.end();
    assert_eq!(memory.load(Ordering::Relaxed), 0);
    // Not depth-tested: never tried.
    let mut t = BandTest::begin(&mut coarse, Some(&memory), false, band, 64);
    t.cover_all([wall.as_slice()].into_iter());
    assert!(t.rows(&far).is_some());
}

#[test]
fn a_polygon_is_drawn_only_on_the_rows_of_tiles_that_do_not_hide_it() {
    let mut coarse = CoarseDepth::default();
    let band = (32, 64);
    // A wall over the band's first two rows of tiles (frame rows 32..48), the whole width.
    let wall = polygon(&[(-10.0, 20.0), (74.0, 20.0), (74.0, 49.6), (-10.0, 49.6)], 0.5);
    let mut t = BandTest::begin(&mut coarse, None, true, band, 64);
    t.cover_all([wall.as_slice()].into_iter());
    // Behind the wall and below it: drawn on the last two rows of tiles only.
    let far = polygon(&[(4.0, 30.0), (40.0, 30.0), (40.0, 60.0), (4.0, 60.0)], 0.1);
    assert!(matches!(t.rows(&far), Some(((48, 64), None))), "behind no tile of the rows drawn");
    // Behind it and inside its tiles: hidden whole; in front of it: every row.
    assert!(t.rows(&polygon(&[(4.0, 33.0), (40.0, 33.0), (40.0, 45.0)], 0.1)).is_none());
    let near = polygon(&[(4.0, 30.0), (40.0, 30.0), (40.0, 60.0)], 0.9);
    assert!(matches!(t.rows(&near), Some((rows, None)) if rows == band), "in front of every floor");
    // A wall over the left two tiles of the middle rows of tiles hides no row of a polygon across all
    // four, only its spans' pixels in those tiles.
    let mut coarse = CoarseDepth::default();
    let left = polygon(&[(-10.0, 38.0), (33.6, 38.0), (33.6, 58.0), (-10.0, 58.0)], 0.5);
    let mut t = BandTest::begin(&mut coarse, None, true, band, 64);
    t.cover_all([left.as_slice()].into_iter());
    let Some((rows, Some(behind))) = t.rows(&far) else { panic!("behind the left tiles") };
    assert_eq!(rows, band);
    assert_eq!(behind.columns(45, (4, 40)), Some((32, 40)));
    assert_eq!(behind.columns(45, (4, 30)), None);
    assert_eq!(behind.columns(35, (4, 40)), Some((4, 40)), "above the wall");
}

#[test]
fn a_polygon_at_depth_zero_never_hides_itself_or_its_like() {
    // Its floor (0, less nothing) equals its greatest depth (0, plus nothing): strictly above is needed.
    let mut coarse = CoarseDepth::default();
    let band = (0, 32);
    let flat = polygon(&[(-10.0, -10.0), (74.0, -10.0), (74.0, 40.0), (-10.0, 40.0)], 0.0);
    let mut t = BandTest::begin(&mut coarse, None, true, band, 64);
    t.cover_all([flat.as_slice(), flat.as_slice()].into_iter());
    assert!(matches!(t.rows(&flat), Some((rows, None)) if rows == band));
    // Behind it, strictly: hidden.
    assert!(t.rows(&polygon(&[(4.0, 4.0), (40.0, 4.0), (40.0, 20.0)], -0.5)).is_none());
    // Corners too large for the fill's slopes raise no floor.
    let mut coarse = CoarseDepth::default();
    let huge = polygon(&[(-10.0, -10.0), (74.0, -10.0), (74.0, 40.0), (-10.0, 40.0)], 3e38);
    let mut t = BandTest::begin(&mut coarse, None, true, band, 64);
    t.cover_all([huge.as_slice()].into_iter());
    assert!(t.rows(&polygon(&[(4.0, 4.0), (40.0, 4.0), (40.0, 20.0)], 1.0)).is_some());
}
