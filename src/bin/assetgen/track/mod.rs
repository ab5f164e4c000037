//! The race circuit: a closed figure-eight of about 4.2 km that crosses over itself on a bridge, written as
//! `circuit.gltf` + `circuit.bin`, its PNG textures and `centerline.json`.
//!
//! The plan is a polygon of hand-placed corner points whose corners are rounded by circular arcs of given
//! radii, so straights and corner radii are exact (a 640 m main straight, hairpins of 32-45 m, sweepers of
//! 150-220 m). Heights come from smooth bumps along the track (the bridge ramps and two crests on
//! embankments); banking is a roll of the cross-section that follows the smoothed curvature. The ground is
//! flat (y = 0) around the circuit and rolls gently further out, up to a ring of distant hills. Everything is
//! made from constants and a fixed-seed PRNG: the same bytes on every run.
//!
//! Conventions: glTF (Y up, metres, counter-clockwise front faces). Every polygon is oriented by the normal it
//! should face ([`MeshBuilder::face`]) and carries a vertex colour from a fixed sun, so the unlit renderer
//! still shows the shape of things (and the banking).
//!
//! [`MeshBuilder::face`]: mesh::MeshBuilder::face

mod circuit;
mod mesh;
mod plan;
mod road;
mod scenery;
mod terrain;
mod textures;
mod util;
mod views;

use std::path::Path;

use glam::Vec3;

use crate::gltf_out::Doc;
use circuit::Circuit;
use mesh::Scene;
use road::{bridge_mesh, grid_slots, start_mesh, track_meshes};
use scenery::{buildings, grandstands, trees};
use terrain::{Terrain, ground_meshes, hills_meshes};
use textures::{Mats, write_textures};
use util::Rng;
use views::{add_cameras, camera_nodes, views, write_centerline};

/// What other generators need to know about the circuit.
#[derive(Clone, Debug, Default)]
pub struct TrackInfo {
    /// Start grid slots: position on the road surface and heading (yaw about +Y, 0 = facing -Z, positive
    /// toward +X: forward = (sin yaw, 0, -cos yaw)).
    pub grid: Vec<(Vec3, f32)>,
    /// Named viewpoints: (name, eye, target).
    pub views: Vec<(String, Vec3, Vec3)>,
}

/// Corner points of the plan (x, z in metres) and the radius of the arc that rounds each, in racing order.
/// The straight into corner 0 climbs over the straight into corner 7 on a bridge.
const CORNERS: [(f32, f32, f32); 11] = [
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
];
/// The straight (into this corner) that carries the bridge.
const BRIDGE_EDGE: usize = 0;
/// The straight (into this corner) with the start line, and how far along it the line is.
const START_EDGE: usize = 1;
const START_AT: f32 = 250.0;
/// Crests on embankments: (plan segment: 2k = straight into corner k, 2k+1 = arc of corner k), fraction along
/// it, height, half-length of the top, length of each ramp.
const CRESTS: [(usize, f32, f32, f32, f32); 2] = [(5, 0.5, 5.0, 30.0, 150.0), (18, 0.5, 4.0, 20.0, 110.0)];

/// Half the road width.
const HALF_WIDTH: f32 = 6.0;
/// Road surface above the ground where the track is at ground level.
const ROAD_LIFT: f32 = 0.08;
/// Centreline sample spacing (the road mesh uses every sample in tight corners and every other elsewhere).
const SAMPLE_STEP: f32 = 5.0;
/// Height of the upper road's embankment at the crossing (road surface ~8.4 m, deck underside ~7.1 m).
const BRIDGE_HEIGHT: f32 = 8.3;
/// Deck thickness under the road on the bridge.
const DECK_DEPTH: f32 = 1.3;
/// Kerb width outside the road edge.
const KERB_WIDTH: f32 = 1.2;
/// Barrier offset from the centreline on straights, and on embankments.
const BARRIER_OFFSET: f32 = 11.0;
const BARRIER_OFFSET_RAISED: f32 = 8.0;
/// Start grid size.
const GRID_SLOTS: usize = 12;
/// Side of the centreline: left, right.
const SIDE: [f32; 2] = [-1.0, 1.0];
/// Ground tile size (the painter's methods need polygons of moderate size), the finer tiles near the track,
/// and the ground's radius.
const TILE: f32 = 100.0;
const FINE_TILE: f32 = 25.0;
/// How far the grass strips beside the track reach beyond the track's corridor (they cover what the finer
/// tiles leave out near the track).
const APRON: f32 = 44.0;
/// Metres per repeat of the grass texture (world-space coordinates, so overlapping grass looks the same).
const GRASS_UV: f32 = 20.0;
const GROUND_RADIUS: f32 = 2150.0;
/// Trees: how far from the centreline they must stay.
const TREE_CLEARANCE: f32 = 30.0;
/// Direction toward the sun (for the baked shading).
const SUN: Vec3 = Vec3::new(0.30, 0.80, 0.52);
const WHITE: Vec3 = Vec3::ONE;

/// Writes `circuit.gltf`, its `.bin`, textures and `centerline.json` into `dir`.
pub fn generate(dir: &Path) -> std::io::Result<TrackInfo> {
    let circuit = Circuit::new()?;
    write_textures(dir)?;
    let mut doc = Doc::new();
    let mats = Mats::new(&mut doc);
    let mut scene = Scene { doc, rng: Rng::new(0x5eed_7ac4), keep_out: vec![] };
    track_meshes(&mut scene, &mats, &circuit);
    bridge_mesh(&mut scene, &mats, &circuit);
    let grid = grid_slots(&circuit);
    start_mesh(&mut scene, &mats, &circuit, &grid);
    let stands = grandstands(&mut scene, &mats, &circuit);
    buildings(&mut scene, &mats, &circuit);
    let terrain = Terrain::new(&circuit);
    ground_meshes(&mut scene, &mats, &circuit, &terrain);
    hills_meshes(&mut scene, &mats, &terrain);
    trees(&mut scene, &mats, &circuit, &terrain);
    let info = TrackInfo { views: views(&circuit, &grid, &stands), grid };
    let cameras = camera_nodes(&mut scene.doc, &info);
    scene.doc.write(dir, "circuit")?;
    add_cameras(&dir.join("circuit.gltf"), cameras)?;
    write_centerline(dir, &circuit)?;
    Ok(info)
}
