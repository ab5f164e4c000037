//! The cars: eight designs, each one glTF file holding a close-up, a middle-range and a long-shot model
//! (seed 003, Namco) with textures of matching resolution, linked by `MSFT_lod`.
//!
//! - close: a lofted body, cabin, four ten-sided wheels, mirrors and (on some) a rear wing, about 240
//!   polygons, textured from a 256x256 atlas; the parts that must stay sharp when enlarged (number plates,
//!   race numbers, head and tail lamps) are separate polygons on a 128x128 detail texture of their own, so
//!   they get several times the atlas's texel density.
//! - mid: a coarse body and cabin and flat wheel discs, 20-30 polygons, on the same atlas box-filtered to 64x64.
//! - long: a hexahedron (6 polygons) on the atlas box-filtered to 16x16.
//!
//! Why these sizes: the models switch where the next coarser texture still has about one texel per pixel.
//! A car is about 4.5 m long and its atlas spends its full width on that length; the switch to the middle
//! model comes when the car's projected bounding sphere is 100 px tall at 720 px (the car then spans about
//! 80 px, and the 64-texel middle atlas gives 0.8 texel per pixel), and to the long shot at 25 px (the
//! 16-texel atlas gives 0.8 texel per pixel over about 20 px). Above 100 px the 256-texel atlas is at most
//! magnified 1:1 until the car is 250 px long, and the detail parts until several times that.

use std::path::Path;

use glam::{Vec3, Vec4};
use serde_json::json;

mod models;
mod paint;
mod spec;

use crate::gltf_out::{Doc, WrapMode};
use models::{close_model, long_model, mid_model};
use paint::{paint_atlas, paint_detail};
use spec::DESIGNS;

/// What the grid scene needs to know about each car file.
#[derive(Clone, Debug)]
pub struct CarInfo {
    /// File stem, e.g. `car_1` (the file is `cars/car_1.gltf`).
    pub name: String,
}

/// Coverage hints for `MSFT_screencoverage` (fractions of a 720-pixel frame): see the module docs.
const COVERAGE: [f32; 3] = [100.0 / 720.0, 25.0 / 720.0, 0.0];

/// Writes one glTF file per design (with its textures) into `dir`.
pub fn generate(dir: &Path) -> std::io::Result<Vec<CarInfo>> {
    let mut out = vec![];
    for (i, d) in DESIGNS.iter().enumerate() {
        let name = format!("car_{}", i + 1);
        let atlas = paint_atlas(d);
        atlas.save(&dir.join(format!("{name}_256.png")))?;
        atlas.downscale(64, 64).save(&dir.join(format!("{name}_64.png")))?;
        atlas.downscale(16, 16).save(&dir.join(format!("{name}_16.png")))?;
        paint_detail(d).save(&dir.join(format!("{name}_detail.png")))?;
        let mut doc = Doc::new();
        let textures = [
            doc.texture(&format!("{name}_256.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_detail.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_64.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_16.png"), WrapMode::Clamp),
        ];
        let white = Vec4::ONE;
        let m_close = doc.material("body 256", white, Some(textures[0]), false, None);
        let m_detail = doc.material("detail 128", white, Some(textures[1]), false, None);
        let m_mid = doc.material("body 64", white, Some(textures[2]), false, None);
        let m_long = doc.material("body 16", white, Some(textures[3]), false, None);
        let close = doc.mesh(&format!("{name} close"), &close_model(d, m_close, m_detail));
        let mid = doc.mesh(&format!("{name} mid"), &mid_model(d, m_mid));
        let long = doc.mesh(&format!("{name} long"), &long_model(d, m_long));
        doc.lod_node(&name, [close, mid, long], COVERAGE, json!({}), true);
        // Cameras for quick looks: front three-quarter, side, rear three-quarter.
        let target = Vec3::new(0.0, 0.5, 0.0);
        doc.camera_node("front", Vec3::new(-4.0, 2.2, -5.5), target, 0.7);
        doc.camera_node("side", Vec3::new(-8.0, 1.0, 0.0), target, 0.7);
        doc.camera_node("rear", Vec3::new(4.5, 2.5, 6.0), target, 0.7);
        doc.write(dir, &name)?;
        out.push(CarInfo { name });
    }
    Ok(out)
}
