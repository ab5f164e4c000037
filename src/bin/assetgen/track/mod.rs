//! The race circuit: a closed figure-eight of about 4.2 km that crosses over itself on a bridge, written as
//! `circuit.gltf` + `circuit.bin`, its PNG textures and `centerline.json`.
//!
//! The plan is a polygon of hand-placed corner points whose corners are rounded by circular arcs of given
//! radii, so straights and corner radii are exact (a 640 m main straight, hairpins of 32-45 m, sweepers of
//! 150-220 m). Heights come from smooth bumps along the track (the bridge ramps and two crests on
//! embankments); banking is a roll of the cross-section that follows the smoothed curvature. The ground is
//! flat (y = 0) around the circuit and rolls gently further out, up to a ring of distant hills. Everything is
//! made from the constants in [`spec`] and a fixed-seed PRNG: the same bytes on every run.
//!
//! Conventions: glTF (Y up, metres, counter-clockwise front faces). Every polygon is oriented by the normal it
//! should face ([`MeshBuilder::face`]) and carries a vertex colour from a fixed sun, so the unlit renderer
//! still shows the shape of things (and the banking).
//!
//! [`MeshBuilder::face`]: mesh::MeshBuilder::face

mod circuit;
mod city;
mod mesh;
mod plan;
mod relief;
mod road;
mod scenery;
mod spec;
mod terrain;
mod textures;
mod util;
mod views;

use std::path::Path;

use glam::{Vec2, Vec3};

use crate::gltf_out::Doc;
use circuit::Circuit;
use city::{city, tunnel_view};
use mesh::Scene;
use relief::{boulders, viaduct_piers};
use road::{bridge_mesh, grid_slots, start_mesh, track_meshes};
use scenery::{PARKLAND, Planting, buildings, grandstands, trees};
pub(crate) use spec::Layout;
use spec::{CIRCUIT, CITY, MOUNTAIN};
use terrain::{Terrain, ground_meshes, hills_meshes};
use textures::{Mats, write_textures};
use util::Rng;
use views::{add_cameras, camera_nodes, mountain_views, views, write_centerline};

/// What other generators need to know about the circuit.
#[derive(Clone, Debug, Default)]
pub struct TrackInfo {
    /// Start grid slots: position on the road surface and heading (yaw about +Y, 0 = facing -Z, positive
    /// toward +X: forward = (sin yaw, 0, -cos yaw)).
    pub grid: Vec<(Vec3, f32)>,
    /// Named viewpoints: (name, eye, target).
    pub views: Vec<(String, Vec3, Vec3)>,
}

/// The courses `assetgen` writes, each into `track/<name>/`.
pub(crate) const COURSES: [&Layout; 3] = [&CIRCUIT, &CITY, &MOUNTAIN];

/// Writes the course `layout` into `dir`: `<name>.gltf`, its `.bin`, textures and `centerline.json`.
pub fn generate(dir: &Path, layout: &'static Layout) -> std::io::Result<TrackInfo> {
    let circuit = Circuit::new(layout)?;
    write_textures(dir, layout.streets, layout.relief.is_some())?;
    let mut doc = Doc::new();
    let mats = Mats::new(&mut doc, layout.streets, layout.relief.is_some());
    let mut scene = Scene { doc, rng: Rng::new(0x5eed_7ac4), keep_out: vec![] };
    let terrain = Terrain::new(&circuit);
    track_meshes(&mut scene, &mats, &circuit, &terrain);
    bridge_mesh(&mut scene, &mats, &circuit);
    let grid = grid_slots(&circuit);
    start_mesh(&mut scene, &mats, &circuit, &grid);
    let info;
    if layout.streets {
        let mut list = views(&circuit, &grid, &[]);
        list.push(tunnel_view(&circuit));
        info = TrackInfo { views: list, grid };
        // No building stands where a view's eye is.
        scene.keep_out.extend(info.views.iter().map(|(_, eye, _)| (Vec2::new(eye.x, eye.z), 12.0)));
        city(&mut scene, &mats, &circuit, &terrain);
        ground_meshes(&mut scene, &mats, &circuit, &terrain);
        hills_meshes(&mut scene, &mats, &terrain);
    } else if let Some(relief) = layout.relief {
        let stands = grandstands(&mut scene, &mats, &circuit);
        ground_meshes(&mut scene, &mats, &circuit, &terrain);
        hills_meshes(&mut scene, &mats, &terrain);
        viaduct_piers(&mut scene, &mats, &circuit, |p| terrain.height(p));
        boulders(&mut scene, &mats, &circuit, relief.boulders, |p| terrain.height(p));
        let forest = Planting { clumps: 500, scattered: 1500, most: relief.trees, margin: 1500.0, roadside: 5000 };
        trees(&mut scene, &mats, &circuit, &terrain, &forest);
        let mut list = views(&circuit, &grid, &stands);
        // The views off the road keep their eyes above the ground.
        list.extend(mountain_views(&circuit).into_iter().map(|(name, eye, target)| {
            let ground = terrain.height(Vec2::new(eye.x, eye.z)) + 2.0;
            (name, Vec3::new(eye.x, eye.y.max(ground), eye.z), target)
        }));
        info = TrackInfo { views: list, grid };
    } else {
        let stands = grandstands(&mut scene, &mats, &circuit);
        buildings(&mut scene, &mats, &circuit);
        ground_meshes(&mut scene, &mats, &circuit, &terrain);
        hills_meshes(&mut scene, &mats, &terrain);
        trees(&mut scene, &mats, &circuit, &terrain, &PARKLAND);
        info = TrackInfo { views: views(&circuit, &grid, &stands), grid };
    }
    let cameras = camera_nodes(&mut scene.doc, &info.views);
    scene.doc.write(dir, layout.name)?;
    add_cameras(&dir.join(format!("{}.gltf", layout.name)), cameras)?;
    write_centerline(dir, &circuit)?;
    Ok(info)
}
