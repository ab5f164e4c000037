//! The fuzz target for the glTF loader, as property tests (proptest), structure-aware like the trace's
//! (`trace_fuzz.rs`): a few valid small documents (a triangle with a camera, a textured quad with an
//! embedded PNG, a sparse accessor, a LOD set by naming convention, the test courtyard) have their JSON
//! mutated (numbers, indices, counts, types and enum values changed; fields removed, duplicated or given
//! the wrong type; node children rewired into DAGs and cycles), and are also packed as GLB whose bytes are
//! then mutated (header and chunk lengths, chunk types, truncation, single bytes). Properties: loading never
//! panics; an error is one non-empty line naming the file; a scene that loads is within its budget (vertices
//! and polygons after instancing, texels, node visits) and draws a small frame without panicking; every input
//! takes bounded time.
//!
//! Run longer with `PROPTEST_CASES=100000 cargo test --test integration gltf_fuzz::` (about 8 s in the dev
//! profile). The first runs (512, then 100,000 cases per property) found one panic: `gltf-json`'s own
//! validation indexes the accessor a primitive's `POSITION` names without checking that it exists (now
//! checked before validation, `asset::validate::check_before_validation`). Reading the crates found two more
//! that these mutations reach too: a GLB header declaring under 12 bytes (`Glb::from_slice` subtracts
//! unchecked) and the cameras and images of `asset::validate::check`.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use base64::Engine;
use proptest::prelude::*;
use scanline_racer::asset::{LoadBudget, LoadedScene, load_from_slice_with_budget};
use scanline_racer::render::{Instance, RenderOptions, Renderer};
use serde_json::{Value, json};

/// A budget small enough that every input loads in milliseconds.
const BUDGET: LoadBudget = LoadBudget {
    file_bytes: 16 << 20,
    buffer_bytes: 16 << 20,
    image_bytes: 16 << 20,
    texels: 1 << 20,
    accessor_values: 1 << 20,
    vertices: 1 << 18,
    polygons: 1 << 17,
    node_visits: 1 << 14,
    node_depth: 64,
    decal_pairs: 1 << 16,
};

/// Most time one input may take (load and a 32x24 frame) in the dev profile.
const MAX_TIME: Duration = Duration::from_secs(5);

fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!("data:{mime};base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The folder external URIs resolve in: one small buffer file and one PNG.
fn base_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf-fuzz");
        std::fs::create_dir_all(&d).unwrap();
        std::fs::write(d.join("a.bin"), f32s(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.])).unwrap();
        std::fs::write(d.join("a.png"), png()).unwrap();
        d
    })
}

fn png() -> Vec<u8> {
    let mut out = vec![];
    image::RgbaImage::from_fn(4, 4, |x, y| image::Rgba([(x * 60) as u8, (y * 60) as u8, 128, 255]))
        .write_to(&mut std::io::Cursor::new(&mut out), image::ImageFormat::Png)
        .unwrap();
    out
}

/// The valid documents mutations start from.
fn seeds() -> &'static [Value] {
    static SEEDS: OnceLock<Vec<Value>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let quad = f32s(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0., 0., 0., 1., 0., 1., 1., 0., 1.]);
        let mut idx: Vec<u8> = [0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()).collect();
        idx.extend([0, 0, 0, 0]);
        let mut quad_buf = quad.clone();
        quad_buf.extend(&idx);
        let triangle = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": 48, "uri": "a.bin"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36, "byteStride": 12}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 4}]}],
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}},
                        {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0, "zfar": 10}}],
            "nodes": [{"mesh": 0, "scale": [-1, 1, 1], "children": [1]}, {"camera": 0, "translation": [0, 0, 3]},
                      {"camera": 1, "rotation": [0, 0, 0, 1]}],
            "scenes": [{"nodes": [0, 2]}],
            "scene": 0,
        });
        let textured = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": quad_buf.len(), "uri": data_uri("application/octet-stream", &quad_buf)}],
            "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                            {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
            "images": [{"uri": data_uri("image/png", &png())}, {"uri": "a.png"}],
            "samplers": [{"wrapS": 33071, "wrapT": 33648}],
            "textures": [{"source": 0, "sampler": 0}, {"source": 1}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor": [1, 1, 1, 1]},
                           "alphaMode": "MASK", "doubleSided": true},
                          {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}],
            "meshes": [{"primitives": [
                {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0},
                {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 1, "mode": 5}]}],
            "nodes": [{"mesh": 0}, {"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1]}],
            "scenes": [{"nodes": [0, 1]}],
        });
        let mut sp = 1u32.to_le_bytes().to_vec();
        sp.extend(f32s(&[1., 1., 1.]));
        let sparse = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": 16, "uri": data_uri("application/octet-stream", &sp)}],
            "bufferViews": [{"buffer": 0, "byteLength": 4}, {"buffer": 0, "byteOffset": 4, "byteLength": 12}],
            "accessors": [{"componentType": 5126, "count": 6, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1],
                "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 1}}}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 6}]}],
            "nodes": [{"children": [1, 1]}, {"mesh": 0}],
            "scenes": [{"nodes": [0]}],
        });
        let lod = json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": 48, "uri": "a.bin"}],
            "bufferViews": [{"buffer": 0, "byteLength": 48}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}, {"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"children": [1, 2, 3], "scale": [1, 1, -1]}, {"name": "car_LOD0", "mesh": 0},
                      {"name": "car_LOD1", "mesh": 1}, {"name": "far", "mesh": 1,
                       "extensions": {"MSFT_lod": {"ids": [1, 2]}}, "extras": {"MSFT_screencoverage": [0.5, 0.1]}}],
            "scenes": [{"nodes": [0]}],
        });
        let courtyard: Value = serde_json::from_slice(
            &std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf")).unwrap(),
        )
        .unwrap();
        vec![triangle, textured, sparse, lod, courtyard]
    })
}

/// One structural change to a document; `at` picks the place by walking the tree.
#[derive(Clone, Debug)]
enum Edit {
    /// Replace a number with an interesting one.
    Number(u64, usize),
    /// Replace a value with one of another type.
    Retype(u64, u8),
    /// Remove an object field or array element.
    Remove(u64),
    /// Duplicate an array element or copy a value over a sibling field.
    Duplicate(u64),
    /// Rewire a node's children (DAGs, self-loops, missing nodes).
    Children(usize, Vec<u8>),
    /// Set a field that names an index, a count or an enum to a chosen value.
    Field(u8, u64, usize),
}

/// Values numbers are set to: indices in and out of range, sizes around limits, enum values.
const NUMBERS: [f64; 24] = [
    0.0,
    1.0,
    -1.0,
    2.0,
    3.0,
    255.0,
    65_536.0,
    16_777_216.0,
    2_147_483_648.0,
    4_294_967_296.0,
    1.8e19,
    1e38,
    -1e38,
    0.5,
    5126.0,
    5125.0,
    0.0,
    1.0,
    2.0,
    3.0,
    4.0,
    5.0,
    6.0,
    7.0,
];
const FIELDS: [&str; 16] = [
    "count",
    "byteLength",
    "byteOffset",
    "byteStride",
    "bufferView",
    "buffer",
    "componentType",
    "type",
    "mode",
    "indices",
    "material",
    "source",
    "mesh",
    "camera",
    "sampler",
    "index",
];

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (any::<u64>(), 0..NUMBERS.len()).prop_map(|(a, n)| Edit::Number(a, n)),
        2 => (any::<u64>(), any::<u8>()).prop_map(|(a, t)| Edit::Retype(a, t)),
        2 => any::<u64>().prop_map(Edit::Remove),
        1 => any::<u64>().prop_map(Edit::Duplicate),
        2 => (0usize..8, proptest::collection::vec(any::<u8>(), 0..6)).prop_map(|(n, c)| Edit::Children(n, c)),
        4 => (any::<u8>(), any::<u64>(), 0..NUMBERS.len()).prop_map(|(f, a, n)| Edit::Field(f, a, n)),
    ]
}

/// The value at a pseudo-random place under `v` (a container's child, chosen by `seed`), at least two
/// levels down where there are two (the top levels' types are the parser's business, not the loader's).
fn pick(v: &mut Value, mut seed: u64) -> &mut Value {
    let mut cur = v;
    let mut depth = 0;
    loop {
        let n = match cur {
            Value::Object(m) => m.len(),
            Value::Array(a) => a.len(),
            _ => 0,
        };
        if n == 0 || (depth >= 2 && seed.is_multiple_of(4)) {
            return cur;
        }
        depth += 1;
        let k = (seed / 4) as usize % n;
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407) >> 1;
        cur = match cur {
            Value::Object(m) => m.values_mut().nth(k).unwrap(),
            Value::Array(a) => &mut a[k],
            _ => unreachable!(),
        };
    }
}

/// Every object under `v` that has `field`.
fn with_field<'v>(v: &'v mut Value, field: &str, out: &mut Vec<&'v mut Value>) {
    if v.get(field).is_some() {
        out.push(v);
        return;
    }
    match v {
        Value::Object(m) => m.values_mut().for_each(|c| with_field(c, field, out)),
        Value::Array(a) => a.iter_mut().for_each(|c| with_field(c, field, out)),
        _ => {}
    }
}

fn number(n: usize) -> Value {
    let x = NUMBERS[n];
    if x.fract() == 0.0 && (0.0..1.9e19).contains(&x) { Value::from(x as u64) } else { Value::from(x) }
}

fn apply(doc: &mut Value, edits: &[Edit]) {
    for e in edits {
        match e {
            Edit::Number(at, n) => {
                let v = pick(doc, *at);
                if v.is_number() {
                    *v = number(*n);
                }
            }
            Edit::Retype(at, t) => {
                *pick(doc, *at) = match t % 6 {
                    0 => Value::Null,
                    1 => Value::from("VEC3"),
                    2 => json!([]),
                    3 => json!({}),
                    4 => Value::from(true),
                    _ => json!([0, 1, 2]),
                };
            }
            Edit::Remove(at) => {
                let v = pick(doc, *at);
                match v {
                    Value::Object(m) if !m.is_empty() => {
                        let k = m.keys().nth(*at as usize % m.len()).cloned().unwrap();
                        m.remove(&k);
                    }
                    Value::Array(a) if !a.is_empty() => {
                        a.remove(*at as usize % a.len());
                    }
                    _ => {}
                }
            }
            Edit::Duplicate(at) => {
                let v = pick(doc, *at);
                match v {
                    Value::Array(a) if !a.is_empty() => {
                        let c = a[*at as usize % a.len()].clone();
                        a.push(c);
                    }
                    Value::Object(m) if m.len() >= 2 => {
                        let keys: Vec<String> = m.keys().cloned().collect();
                        let from = m[&keys[*at as usize % keys.len()]].clone();
                        m.insert(keys[(*at as usize / 7) % keys.len()].clone(), from);
                    }
                    _ => {}
                }
            }
            Edit::Children(node, children) => {
                if let Some(nodes) = doc.get_mut("nodes").and_then(Value::as_array_mut) {
                    let n = nodes.len().max(1);
                    if let Some(node) = nodes.get_mut(node % n).filter(|v| v.is_object()) {
                        node["children"] = children.iter().map(|&c| Value::from(c as usize % (n + 1))).collect();
                    }
                }
            }
            Edit::Field(f, at, n) => {
                let field = FIELDS[*f as usize % FIELDS.len()];
                let mut found = vec![];
                with_field(doc, field, &mut found);
                if !found.is_empty() {
                    let k = *at as usize % found.len();
                    found.swap_remove(k)[field] = number(*n);
                }
            }
        }
    }
}

/// The document as GLB: its first buffer, if a data URI, moved into the BIN chunk.
fn glb(doc: &Value) -> Vec<u8> {
    let mut doc = doc.clone();
    let mut bin = vec![];
    if let Some(uri) = doc.pointer("/buffers/0/uri").and_then(Value::as_str)
        && let Some((_, b64)) = uri.split_once(";base64,")
    {
        bin = base64::engine::general_purpose::STANDARD.decode(b64).unwrap_or_default();
        doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut json = serde_json::to_vec(&doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}

/// One change to GLB bytes.
#[derive(Clone, Debug)]
enum ByteEdit {
    /// Rewrite the header's total length.
    Total(u32),
    /// Rewrite the JSON chunk's length.
    JsonLen(u32),
    /// Rewrite the BIN chunk's length (found after the JSON chunk).
    BinLen(u32),
    /// Rewrite a chunk type (0: JSON's, 1: BIN's) to 4 bytes.
    ChunkType(bool, [u8; 4]),
    /// Cut the file at (index mod length).
    Cut(usize),
    /// Set one byte.
    Set(usize, u8),
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    let len = prop_oneof![Just(0u32), Just(11), Just(12), Just(u32::MAX), any::<u32>(), 0u32..4096];
    prop_oneof![
        1 => len.clone().prop_map(ByteEdit::Total),
        1 => len.clone().prop_map(ByteEdit::JsonLen),
        1 => len.prop_map(ByteEdit::BinLen),
        1 => (any::<bool>(), prop_oneof![Just(*b"JSON"), Just(*b"BIN\0"), any::<[u8; 4]>()])
            .prop_map(|(bin, t)| ByteEdit::ChunkType(bin, t)),
        1 => any::<usize>().prop_map(ByteEdit::Cut),
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| ByteEdit::Set(i, b)),
    ]
}

fn apply_bytes(b: &mut Vec<u8>, edits: &[ByteEdit]) {
    for e in edits {
        let json_len = b.get(12..16).map_or(0, |s| u32::from_le_bytes(s.try_into().unwrap()) as usize);
        let bin_at = 20 + json_len;
        let mut put = |at: usize, bytes: &[u8]| {
            if let Some(dst) = b.get_mut(at..at + bytes.len()) {
                dst.copy_from_slice(bytes);
            }
        };
        match e {
            ByteEdit::Total(n) => put(8, &n.to_le_bytes()),
            ByteEdit::JsonLen(n) => put(12, &n.to_le_bytes()),
            ByteEdit::BinLen(n) => put(bin_at, &n.to_le_bytes()),
            ByteEdit::ChunkType(bin, t) => put(if *bin { bin_at + 4 } else { 16 }, t),
            ByteEdit::Cut(i) if !b.is_empty() => b.truncate(i % b.len()),
            ByteEdit::Set(i, v) if !b.is_empty() => {
                let n = b.len();
                b[i % n] = *v;
            }
            _ => {}
        }
    }
}

/// Loads `bytes` and checks the properties; returns whether it loaded.
fn check(bytes: &[u8]) -> bool {
    let start = Instant::now();

    let loaded = match load_from_slice_with_budget(bytes, base_dir(), "fuzz.gltf", &BUDGET) {
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.is_empty() && !msg.contains('\n'), "error is not one line: {msg:?}");
            assert!(msg.starts_with("fuzz.gltf: "), "error does not name the file: {msg}");
            false
        }
        Ok(scene) => {
            within_budget(&scene);
            draw(&scene);
            true
        }
    };
    assert!(start.elapsed() < MAX_TIME, "took {:?}", start.elapsed());
    loaded
}

fn within_budget(scene: &LoadedScene) {
    let size = |i: &Instance, f: &dyn Fn(usize) -> usize| -> usize {
        match i.lod {
            Some(set) => scene.lod_sets[set].meshes.iter().map(|&m| f(m)).max().unwrap_or(0),
            None => f(i.mesh),
        }
    };
    let vertices: usize = scene.instances.iter().map(|i| size(i, &|m| scene.meshes[m].vertices().len())).sum();
    let polygons: usize = scene.instances.iter().map(|i| size(i, &|m| scene.meshes[m].polygons().len())).sum();
    let texels: u64 = scene.textures.iter().map(|t| u64::from(t.width()) * u64::from(t.height())).sum();
    assert!(vertices as u64 <= BUDGET.vertices, "{vertices} vertices after instancing");
    assert!(polygons as u64 <= BUDGET.polygons, "{polygons} polygons after instancing");
    assert!(texels <= BUDGET.texels, "{texels} texels");
    assert!(scene.instances.len() as u64 <= BUDGET.node_visits);
    // Stored meshes: each placed at least once, or a mirrored copy of one, or a LOD level.
    let stored: usize = scene.meshes.iter().map(|m| m.vertices().len()).sum();
    assert!(stored as u64 <= 6 * BUDGET.vertices, "{stored} vertices stored");
}

fn draw(scene: &LoadedScene) {
    let (w, h) = (32, 24);
    let camera = scene.cameras.first().map_or_else(|| scene.framing_camera(w as f32 / h as f32), |c| c.camera);
    let mut frame = vec![0u32; w * h];
    let options = RenderOptions { threads: 1, ..RenderOptions::default() };
    let _ = Renderer::new().render(&mut frame, w, h, &camera, &scene.draw_list(), &options);
}

/// Cases per property: 512, or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_json_never_panics_and_what_loads_is_within_budget(
        seed in 0..5usize, edits in proptest::collection::vec(edit(), 1..6),
    ) {
        let mut doc = seeds()[seed].clone();
        apply(&mut doc, &edits);
        check(&serde_json::to_vec(&doc).unwrap());
    }

    #[test]
    fn mutated_glb_never_panics_and_what_loads_is_within_budget(
        seed in 0..5usize,
        edits in proptest::collection::vec(edit(), 0..4),
        bytes in proptest::collection::vec(byte_edit(), 0..3),
    ) {
        let mut doc = seeds()[seed].clone();
        apply(&mut doc, &edits);
        let mut b = glb(&doc);
        apply_bytes(&mut b, &bytes);
        check(&b);
    }
}

#[test]
fn every_seed_loads_as_gltf_and_as_glb() {
    for (k, doc) in seeds().iter().enumerate() {
        assert!(check(&serde_json::to_vec(doc).unwrap()), "seed {k} as glTF");
        assert!(check(&glb(doc)), "seed {k} as GLB");
    }
}
