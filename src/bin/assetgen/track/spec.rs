//! The circuit's specification: its plan, heights and dimensions, the ground around it, and the light and
//! tint its polygons are shaded with.
//!
//! These are the numbers the children of `track` share (the circuit is sampled from them, the road, scenery
//! and terrain are built to them). They live in a file of their own, which imports nothing from `track`, so
//! that the children never reach back into `track/mod.rs`: the parent ties the children together and hands
//! records down, nothing flows back up.

use glam::Vec3;

// The plans.

/// What makes one course differ from another: its plan, heights, barriers and look.
pub(crate) struct Layout {
    /// The folder name under `assets/track/` and the file stem of its glTF.
    pub(crate) name: &'static str,
    /// Its title (the menus and `scanline-racer courses` show it).
    pub(super) title: &'static str,
    /// One sentence on what it is like (shown beside the title).
    pub(super) about: &'static str,
    /// Corner points of the plan (x, z in metres) and the radius of the arc that rounds each, in racing order.
    pub(super) corners: &'static [(f32, f32, f32)],
    /// The straight (into this corner) that carries the bridge over another straight.
    pub(super) bridge_edge: usize,
    /// The straight (into this corner) with the start line.
    pub(super) start_edge: usize,
    /// How far along the straight `start_edge` the start line is, in metres.
    pub(super) start_at: f32,
    /// Crests on embankments: (plan segment: 2k = straight into corner k, 2k+1 = arc of corner k), fraction
    /// along it, height, half-length of the top, length of each ramp.
    pub(super) crests: &'static [(usize, f32, f32, f32, f32)],
    /// Barrier offset from the centreline on straights.
    pub(super) barrier_offset: f32,
    /// Whether the barriers move out (over gravel) on the outside of tight corners.
    pub(super) run_off: bool,
    /// Whether the course is a street course: pavement for grass, buildings for trees.
    pub(super) streets: bool,
    /// The corners the "hairpin" and "sweeper" views look at.
    pub(super) view_corners: [usize; 2],
    /// The heights of a course in the hills (none: the course lies on the plain at y = 0).
    pub(super) relief: Option<&'static Relief>,
}

/// The heights of a course in the hills: the road's level along the lap, its viaduct, and the ground's peaks
/// and gorge away from the road.
pub(super) struct Relief {
    /// The ground level under the road at knots (plan segment, fraction along it, metres), in racing order:
    /// linear between knots, then smoothed; the plain (0 m) before the first knot and after the last.
    pub(super) knots: &'static [(usize, f32, f32)],
    /// The viaduct: (plan segment, fraction where it leaves the ground, fraction where it lands).
    pub(super) viaduct: (usize, f32, f32),
    /// The ground's peaks away from the road: (x, z, height, radius) of a Gaussian bump.
    pub(super) peaks: &'static [(f32, f32, f32, f32)],
    /// The gorge under the viaduct: its line's two ends (x, z), its depth (deepest at the middle of the
    /// line) and its half-width.
    pub(super) gorge: ((f32, f32), (f32, f32), f32, f32),
    /// How many trees stand on the slopes.
    pub(super) trees: usize,
    /// How many boulders lie on the slopes near the road.
    pub(super) boulders: usize,
}

/// The race circuit: a figure-eight of about 4.2 km in open country.
pub(crate) const CIRCUIT: Layout = Layout {
    name: "circuit",
    title: "Green Valley Circuit",
    about: "a fast figure-eight in open country: long straights, sweepers, two hairpins and a bridge",
    corners: &[
        (-130.0, 360.0, 45.0),   // 0: tight left onto the main straight
        (670.0, 360.0, 170.0),   // 1: fast left at the end of the main straight
        (760.0, 70.0, 220.0),    // 2: fast left over the first crest
        (710.0, -200.0, 32.0),   // 3: hairpin
        (535.0, -150.0, 70.0),   // 4: right
        (390.0, -290.0, 60.0),   // 5: left
        (120.0, -260.0, 150.0),  // 6: fast left onto the diagonal that passes under the bridge
        (-300.0, 215.0, 35.0),   // 7: tight right
        (-600.0, 260.0, 160.0),  // 8: long fast right
        (-655.0, -170.0, 40.0),  // 9: tight right after the second crest
        (-385.0, -285.0, 150.0), // 10: fast right onto the diagonal that climbs over the bridge
    ],
    bridge_edge: 0,
    start_edge: 1,
    start_at: 250.0,
    crests: &[(5, 0.5, 5.0, 30.0, 150.0), (18, 0.5, 4.0, 20.0, 110.0)],
    barrier_offset: 11.0,
    run_off: true,
    streets: false,
    view_corners: [3, 8],
    relief: None,
};

/// The street course: about 3.5 km of city blocks, tight corners, a tunnel, and an overpass where the road
/// crosses itself.
pub(crate) const CITY: Layout = Layout {
    name: "city",
    title: "Harbour Streets",
    about: "a street course between buildings: tight corners, a tunnel and an overpass",
    corners: &[
        (0.0, 0.0, 18.0),       // 0: left out of the diagonal onto the harbour front
        (620.0, 0.0, 20.0),     // 1: right at the end of the harbour front
        (620.0, 380.0, 16.0),   // 2: right
        (380.0, 380.0, 14.0),   // 3: right onto the avenue that climbs over the harbour front
        (380.0, -320.0, 18.0),  // 4: left at the bottom of the overpass, onto the start straight
        (-260.0, -320.0, 22.0), // 5: left into the tunnel street
        (-260.0, 260.0, 16.0),  // 6: left
        (-80.0, 260.0, 14.0),   // 7: tight left onto the diagonal
    ],
    bridge_edge: 4,
    start_edge: 5,
    start_at: 300.0,
    crests: &[],
    barrier_offset: 8.5,
    run_off: false,
    streets: true,
    view_corners: [3, 6],
    relief: None,
};

/// The mountain course: about 5.7 km from a plain up a mountainside by two hairpins, along a ridge 100 m up
/// with the plain laid out below, and down over a viaduct to a bridge across the start straight.
pub(crate) const MOUNTAIN: Layout = Layout {
    name: "mountain",
    title: "Eagle Pass",
    about: "a mountain road: a climb by two hairpins, a ridge with a view, a viaduct over a gorge",
    corners: &[
        (-400.0, -400.0, 55.0),  // 0: right onto the start straight
        (380.0, 380.0, 70.0),    // 1: left at the foot of the climb
        (560.0, 740.0, 26.0),    // 2: left onto the first climbing leg
        (180.0, 830.0, 24.0),    // 3: right hairpin
        (600.0, 930.0, 26.0),    // 4: left hairpin onto the ridge
        (-450.0, 1000.0, 140.0), // 5: fast left at the end of the ridge
        (-640.0, 560.0, 90.0),   // 6: left onto the viaduct, down to the bridge
        (420.0, -420.0, 50.0),   // 7: right at the bottom
        (0.0, -700.0, 110.0),    // 8: fast right back to the start
    ],
    bridge_edge: 7,
    start_edge: 1,
    start_at: 250.0,
    crests: &[],
    barrier_offset: 10.0,
    run_off: true,
    streets: false,
    view_corners: [3, 5],
    relief: Some(&Relief {
        knots: &[
            (3, 0.5, 0.0),
            (5, 0.5, 28.0),
            (7, 0.5, 54.0),
            (9, 0.5, 74.0),
            (10, 0.45, 104.0),
            (11, 0.5, 92.0),
            (13, 0.5, 56.0),
            (14, 0.42, 0.0),
        ],
        viaduct: (14, 0.03, 0.29),
        peaks: &[
            (0.0, 1750.0, 520.0, 420.0),
            (-1150.0, 1250.0, 400.0, 360.0),
            (1150.0, 1400.0, 380.0, 380.0),
            (1000.0, -1000.0, 140.0, 420.0),
            (-1150.0, -800.0, 110.0, 380.0),
        ],
        gorge: ((-935.0, -121.0), (-250.0, 620.0), 45.0, 120.0),
        trees: 8000,
        boulders: 1400,
    }),
};

// The road and what stands beside it.

/// Half the road width.
pub(super) const HALF_WIDTH: f32 = 6.0;
/// Road surface above the ground where the track is at ground level.
pub(super) const ROAD_LIFT: f32 = 0.08;
/// Centreline sample spacing (the road mesh uses every sample in tight corners and every other elsewhere).
pub(super) const SAMPLE_STEP: f32 = 5.0;
/// Height of the upper road's embankment at the crossing (road surface ~8.4 m, deck underside ~7.1 m).
pub(super) const BRIDGE_HEIGHT: f32 = 8.3;
/// Deck thickness under the road on the bridge.
pub(super) const DECK_DEPTH: f32 = 1.3;
/// Kerb width outside the road edge.
pub(super) const KERB_WIDTH: f32 = 1.2;
/// Barrier offset from the centreline on embankments.
pub(super) const BARRIER_OFFSET_RAISED: f32 = 8.0;
/// Start grid size.
pub(super) const GRID_SLOTS: usize = 12;
/// Side of the centreline: left, right.
pub(super) const SIDE: [f32; 2] = [-1.0, 1.0];

// The ground.

/// Ground tile size (the painter's methods need polygons of moderate size).
pub(super) const TILE: f32 = 100.0;
/// The finer ground tiles near the track.
pub(super) const FINE_TILE: f32 = 25.0;
/// The ground's radius.
pub(super) const GROUND_RADIUS: f32 = 2150.0;
/// How far the grass strips beside the track reach beyond the track's corridor (they cover what the finer
/// tiles leave out near the track).
pub(super) const APRON: f32 = 44.0;
/// Metres per repeat of the grass texture (world-space coordinates, so overlapping grass looks the same).
pub(super) const GRASS_UV: f32 = 20.0;
/// Trees: how far from the centreline they must stay.
pub(super) const TREE_CLEARANCE: f32 = 30.0;

// Shading.

/// Direction toward the sun (for the baked shading).
pub(super) const SUN: Vec3 = Vec3::new(0.30, 0.80, 0.52);
/// The tint of a polygon that shows its texture's own colours (under the baked light only).
pub(super) const WHITE: Vec3 = Vec3::ONE;
