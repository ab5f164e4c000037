//! Cut-outs trimmed at load: a glTF quad of an alpha-masked texture whose opaque part is a disc loads as
//! one polygon around the disc, and draws the same pixels as the whole quad while shading far fewer.

use std::path::Path;

use base64::Engine;
use glam::{Vec2, Vec4};
use scanline_racer::render::{MeshBuilder, Quality, RenderOptions, Vertex};
use serde_json::json;

use crate::common::{pixel_camera, render};

const SIZE: usize = 256;

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// A 32x32 PNG, clear but for an opaque disc of radius 9 texels at (16, 14), striped so that texels show.
fn disc_png() -> Vec<u8> {
    let img = image::RgbaImage::from_fn(32, 32, |x, y| {
        let (fx, fy) = (x as f32 + 0.5 - 16.0, y as f32 + 0.5 - 14.0);
        let a = if fx * fx + fy * fy < 81.0 { 255 } else { 0 };
        image::Rgba([(40 + x * 6) as u8, (200 - y * 5) as u8, 90, a])
    });
    let mut out = vec![];
    img.write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png).unwrap();
    out
}

/// The quad's corners in the pixel camera's world (x 32..224, y 32..224, so 6 pixels a texel) and its
/// texture coordinates (v down the texture, as the image's rows).
fn corners() -> [([f32; 3], [f32; 2]); 4] {
    [
        ([32.0, 32.0, 0.0], [0.0, 1.0]),
        ([224.0, 32.0, 0.0], [1.0, 1.0]),
        ([224.0, 224.0, 0.0], [1.0, 0.0]),
        ([32.0, 224.0, 0.0], [0.0, 0.0]),
    ]
}

/// The cut-out as a glTF file; `bend` moves the last corner's texture coordinates off the affine map, so
/// that the two triangles are not merged into one quad.
fn gltf(bend: f32) -> Vec<u8> {
    let mut buf: Vec<u8> = corners().iter().flat_map(|c| c.0).flat_map(f32::to_le_bytes).collect();
    let mut uvs = corners().map(|c| c.1);
    uvs[3][0] += bend;
    buf.extend(uvs.iter().flatten().flat_map(|x| x.to_le_bytes()));
    buf.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": buf.len(), "uri": data_uri("application/octet-stream", &buf)}],
        "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [32, 32, 0], "max": [224, 224, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "images": [{"uri": data_uri("image/png", &disc_png())}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "alphaMode": "MASK", "doubleSided": true}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    });
    serde_json::to_vec(&doc).unwrap()
}

#[test]
fn a_cut_out_quad_loads_trimmed_and_draws_the_same_pixels_for_fewer_shaded() {
    let scene = scanline_racer::asset::load_from_slice(&gltf(0.0), Path::new("."), "cutout.gltf").unwrap();
    let trimmed = &scene.meshes[0];
    let polys = trimmed.polygons();
    assert_eq!(polys.len(), 1, "one polygon, as the quad was");
    let n = trimmed.polygon_indices(&polys[0]).len();
    assert!((5..=9).contains(&n), "{n} corners");
    // The whole quad with the same material, as it was before trimming.
    let mut b = MeshBuilder::new();
    let m = b.material(trimmed.materials()[0].clone());
    let idx: Vec<u32> = corners()
        .iter()
        .map(|&(p, uv)| b.vertex(Vertex { position: p.into(), uv: Vec2::from(uv), color: Vec4::ONE }))
        .collect();
    b.polygon(&idx, m);
    let whole = b.build().unwrap();
    let camera = pixel_camera(SIZE, SIZE);
    for options in [RenderOptions::default(), Quality::Ultra.apply(RenderOptions::default())] {
        let (a, sa) = render(std::slice::from_ref(trimmed), &scene.textures, &camera, SIZE, SIZE, &options);
        let (b, sb) = render(std::slice::from_ref(&whole), &scene.textures, &camera, SIZE, SIZE, &options);
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(differ, 0, "{differ} pixels differ");
        assert_eq!(sa.pixels_written, sb.pixels_written);
        // The disc and its margin: well under half the quad.
        assert!(sa.pixels_written > 0 && sa.pixels_shaded * 2 < sb.pixels_shaded, "{sa:?} against {sb:?}");
    }
}

#[test]
fn cut_out_triangles_sharing_an_edge_stay_whole() {
    // Two triangles (not one quad: the bent corner breaks the affine map) share the diagonal; trimming
    // either alone would cut that edge where the other does not, leaving a crack.
    let scene = scanline_racer::asset::load_from_slice(&gltf(0.01), Path::new("."), "cutout.gltf").unwrap();
    let mesh = &scene.meshes[0];
    let counts: Vec<usize> = mesh.polygons().iter().map(|p| mesh.polygon_indices(p).len()).collect();
    assert_eq!(counts, [3, 3]);
    assert_eq!(mesh.vertices().len(), 4);
}
