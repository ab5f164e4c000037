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
