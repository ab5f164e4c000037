//! Hostile glTF files found by adversarial runs, each kept as a regression test. Most run the real binary
//! (`render FILE --out X.png`, the user's path) under a memory bound (RLIMIT_AS through `ulimit -v`) and a
//! wall-time bound (the child is killed past it), and assert exit 1 with exactly one stderr line naming the
//! problem, or exit 0 where the file is honest and only its cost was the bug; a few check the loader's
//! bookkeeping through the library with a small [`LoadBudget`].
//!
//! Every file is generated here (large ones as sparse files, which take no disk), except
//! `tests/hostile/black-8192.png`: an 8,229-byte 1-bit PNG of 8192x8192 black texels (made with Python's
//! `zlib`: one IHDR of bit depth 1, one IDAT of 8192 zero rows compressed at level 9, IEND).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use base64::Engine;
use scanline_racer::asset::{AssetError, LoadBudget, load_from_slice, load_from_slice_with_budget};
use serde_json::{Value, json};

const MIB: u64 = 1 << 20;

/// Tests that take hundreds of MiB run one at a time (the harness runs tests in parallel).
static HEAVY: Mutex<()> = Mutex::new(());

fn heavy() -> std::sync::MutexGuard<'static, ()> {
    HEAVY.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A fresh folder for one test's files.
fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hostile-gltf").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write_json(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_vec(v).unwrap()).unwrap();
    p
}

/// A file of `len` zero bytes that takes no disk space.
fn sparse_file(path: &Path, len: u64) {
    std::fs::File::create(path).unwrap().set_len(len).unwrap();
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A glTF of one triangle facing +z (counter-clockwise seen from +z), as buffer 0 / view 0 / accessor 0 /
/// mesh 0, with `extra` merged over it.
fn triangle_doc(extra: Value) -> Value {
    let tri = f32s(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    let mut doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": data_uri(&tri)}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    });
    for (k, v) in extra.as_object().unwrap() {
        doc[k] = v.clone();
    }
    doc
}

/// A glTF whose accessor 0 has `count` VEC3 elements, all zero but one, stored sparse with no bufferView
/// (a few hundred bytes for any count), used by `meshes` meshes; `nodes` and scenes are the caller's.
fn sparse_doc(count: u64, meshes: usize, nodes: Value, roots: Value) -> Value {
    let mut sp = 0u32.to_le_bytes().to_vec();
    sp.extend(f32s(&[1., 1., 1.]));
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 16, "uri": data_uri(&sp)}],
        "bufferViews": [{"buffer": 0, "byteLength": 4}, {"buffer": 0, "byteOffset": 4, "byteLength": 12}],
        "accessors": [{"componentType": 5126, "count": count, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1],
            "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 1}}}],
        "meshes": (0..meshes).map(|_| json!({"primitives": [{"attributes": {"POSITION": 0}}]})).collect::<Vec<_>>(),
        "nodes": nodes,
        "scenes": [{"nodes": roots}],
    })
}

/// A 71x71 grid of quads cut to 10,000 triangles (5,000 quads once merged), placed by `instances` nodes.
fn grid_doc(instances: usize) -> Value {
    let g = 71u32;
    let mut pos = vec![];
    for j in 0..=g {
        for i in 0..=g {
            pos.extend([i as f32 / g as f32, j as f32 / g as f32, 0.0]);
        }
    }
    let mut idx: Vec<u16> = vec![];
    for j in 0..g {
        for i in 0..g {
            let a = (j * (g + 1) + i) as u16;
            let (b, c, e) = (a + 1, a + g as u16 + 2, a + g as u16 + 1);
            idx.extend([a, b, c, a, c, e]);
        }
    }
    idx.truncate(30_000);
    let mut bytes = f32s(&pos);
    let plen = bytes.len();
    bytes.extend(idx.iter().flat_map(|i| i.to_le_bytes()));
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(), "uri": data_uri(&bytes)}],
        "bufferViews": [{"buffer": 0, "byteLength": plen}, {"buffer": 0, "byteOffset": plen, "byteLength": idx.len() * 2}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": pos.len() / 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5123, "count": idx.len(), "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": (0..instances).map(|k| json!({"mesh": 0, "translation": [(k % 60) as f32 * 1.1, (k / 60) as f32 * 1.1, 0.0]})).collect::<Vec<_>>(),
        "scenes": [{"nodes": (0..instances).collect::<Vec<_>>()}],
    })
}

/// What a bounded run of the binary did.
struct Run {
    code: Option<i32>,
    stderr: String,
}

/// Runs `scanline-racer ARGS` with its address space limited to `mem_mib` MiB and killed after `secs`
/// seconds. (`MALLOC_ARENA_MAX` keeps glibc from reserving an arena of address space per thread, which
/// would make the limit depend on the core count.)
fn run_bounded(args: &[&str], mem_mib: u64, secs: u64) -> Run {
    let start = Instant::now();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v \"$0\" && exec \"$@\"")
        .arg((mem_mib * 1024).to_string())
        .arg(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(args)
        .env("MALLOC_ARENA_MAX", "2")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run scanline-racer");
    let deadline = start + Duration::from_secs(secs);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("{args:?} did not finish within {secs} s");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let out = child.wait_with_output().unwrap();
    Run { code: out.status.code(), stderr: String::from_utf8_lossy(&out.stderr).into_owned() }
}

/// `render FILE --out X.png` (small frame, two threads) under the bounds.
fn render(file: &Path, mem_mib: u64, secs: u64) -> Run {
    let out = file.with_extension("png");
    let args = ["render", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--width", "64", "--height", "48"];
    run_bounded(&[&args[..], &["--threads", "2"][..]].concat(), mem_mib, secs)
}

/// Exit 1, one line on stderr, no panic, mentioning every needle.
fn assert_refused(r: &Run, needles: &[&str]) {
    assert_eq!(r.code, Some(1), "stderr: {}", r.stderr);
    assert!(!r.stderr.contains("panicked"), "panic: {}", r.stderr);
    assert_eq!(r.stderr.trim_end().lines().count(), 1, "expected one line, got: {}", r.stderr);
    assert!(r.stderr.starts_with("scanline-racer: error: "), "{}", r.stderr);
    for n in needles {
        assert!(r.stderr.contains(n), "expected '{n}' in: {}", r.stderr);
    }
}

fn assert_drawn(r: &Run) {
    assert_eq!(r.code, Some(0), "stderr: {}", r.stderr);
}

// 1. Panics inside the gltf crate on documents its validation lets through.

#[test]
fn fields_the_gltf_crate_would_unwrap_are_refused_in_one_line() {
    let d = dir("unwrap");
    let camera = |kind: &str, object: &str, body: Value| {
        triangle_doc(json!({
            "cameras": [{"type": kind, object: body}],
            "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
            "scenes": [{"nodes": [0, 1]}],
        }))
    };
    let textured = |image: Value| {
        let mut doc = triangle_doc(json!({
            "images": [image],
            "textures": [{"source": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        }));
        doc["meshes"][0]["primitives"][0]["material"] = 0.into();
        doc
    };
    let cases = [
        (
            "ortho.gltf",
            camera("orthographic", "perspective", json!({"yfov": 0.8, "znear": 0.1})),
            "camera 0: type is orthographic but it has no 'orthographic' object",
        ),
        (
            "persp.gltf",
            camera("perspective", "orthographic", json!({"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10})),
            "camera 0: type is perspective but it has no 'perspective' object",
        ),
        ("noimage.gltf", textured(json!({})), "image 0: has neither a uri nor a bufferView"),
        ("nomime.gltf", textured(json!({"bufferView": 0})), "image 0: has a bufferView but no mimeType"),
        // The crate's own validation indexes this accessor unchecked (found by tests/integration/gltf_fuzz.rs).
        (
            "position.gltf",
            {
                let mut doc = triangle_doc(json!({}));
                doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9.into();
                doc
            },
            "mesh 0 primitive 0: POSITION names accessor 9, which does not exist",
        ),
    ];
    for (name, doc, needle) in cases {
        let r = render(&write_json(&d, name, &doc), 256, 20);
        assert_refused(&r, &[name, needle]);
    }
    // A GLB header declaring fewer bytes than the header itself (the crate subtracts 12 unchecked).
    for declared in [0u32, 11] {
        let p = d.join(format!("short-{declared}.glb"));
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(declared.to_le_bytes());
        glb.extend([0u8; 20]);
        std::fs::write(&p, glb).unwrap();
        assert_refused(&render(&p, 256, 20), &["not a valid glTF 2.0 file", "GLB header declares"]);
    }
}

// 2. One load budget.

#[test]
fn buffers_naming_one_file_read_it_once() {
    let _heavy = heavy();
    let d = dir("buffers-once");
    sparse_file(&d.join("big.bin"), 128 * MIB);
    let mut doc = triangle_doc(json!({}));
    for _ in 0..8 {
        doc["buffers"].as_array_mut().unwrap().push(json!({"byteLength": 128 * MIB, "uri": "big.bin"}));
    }
    // Each name read separately would take 1 GiB; once, 128 MiB.
    let r = render(&write_json(&d, "eight.gltf", &doc), 448, 30);
    assert_drawn(&r);
}

#[test]
fn buffers_over_the_total_budget_are_refused_before_reading() {
    let d = dir("buffers-total");
    let mut doc = triangle_doc(json!({}));
    for k in 0..3 {
        sparse_file(&d.join(format!("part{k}.bin")), 400 * MIB);
        doc["buffers"].as_array_mut().unwrap().push(json!({"byteLength": 400 * MIB, "uri": format!("part{k}.bin")}));
    }
    // 1.2 GiB over the 1 GiB budget, refused before any is read: 192 MiB of address space is enough.
    let r = render(&write_json(&d, "three.gltf", &doc), 192, 20);
    assert_refused(&r, &["buffer 3", "LoadBudget::buffer_bytes"]);
}

/// A textured triangle per image, each image naming `uris[k]`.
fn textured_doc(uris: &[String]) -> Value {
    let n = uris.len();
    let bytes = f32s(&[0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1.]);
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 60, "uri": data_uri(&bytes)}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}],
        "images": uris.iter().map(|u| json!({"uri": u})).collect::<Vec<_>>(),
        "textures": (0..n).map(|i| json!({"source": i})).collect::<Vec<_>>(),
        "materials": (0..n).map(|i| json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}})).collect::<Vec<_>>(),
        "meshes": (0..n).map(|i| json!({"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": i}]})).collect::<Vec<_>>(),
        "nodes": (0..n).map(|i| json!({"mesh": i})).collect::<Vec<_>>(),
        "scenes": [{"nodes": (0..n).collect::<Vec<_>>()}],
    })
}

fn black_png() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile/black-8192.png")).unwrap()
}

#[test]
fn images_naming_one_png_decode_it_once() {
    let _heavy = heavy();
    let d = dir("images-once");
    std::fs::write(d.join("black.png"), black_png()).unwrap();
    // Twelve names (two spellings) of one 8192x8192 PNG: 12 decodes took 3.4 GB, one takes about 0.5 GB.
    let uris: Vec<String> =
        (0..12).map(|k| if k % 2 == 0 { "black.png".into() } else { "./black.png".into() }).collect();
    let r = render(&write_json(&d, "twelve.gltf", &textured_doc(&uris)), 1024, 60);
    assert_drawn(&r);
}

#[test]
fn decoded_texels_over_the_budget_are_refused() {
    let _heavy = heavy();
    let d = dir("images-total");
    // Three different files of 8192x8192 (64 Mi texels each; the budget is 128 Mi): bytes after IEND make
    // them different sources, which decoders ignore.
    let uris: Vec<String> = (0..3u8)
        .map(|k| {
            let mut png = black_png();
            png.push(k);
            std::fs::write(d.join(format!("black{k}.png")), png).unwrap();
            format!("black{k}.png")
        })
        .collect();
    let r = render(&write_json(&d, "three.gltf", &textured_doc(&uris)), 1280, 60);
    assert_refused(&r, &["image 2", "LoadBudget::texels"]);
}

#[test]
fn instancing_past_the_polygon_budget_is_refused() {
    // 3,000 nodes placing one 10,000-triangle mesh: 15 M polygons once merged into quads, 5.9 GB to draw.
    let d = dir("instances");
    let p = write_json(&d, "grid3000.gltf", &grid_doc(3000));
    assert!(std::fs::metadata(&p).unwrap().len() < 700_000);
    let r = render(&p, 256, 20);
    assert_refused(&r, &["node 838", "polygons after instancing", "LoadBudget::polygons"]);
}

#[test]
fn a_huge_sparse_accessor_shared_by_meshes_is_refused_before_it_is_read() {
    let d = dir("sparse");
    let doc = sparse_doc(1 << 24, 3, json!([{"mesh": 0}, {"mesh": 1}, {"mesh": 2}]), json!([0, 1, 2]));
    let p = write_json(&d, "sparse.gltf", &doc);
    assert!(std::fs::metadata(&p).unwrap().len() < 1000);
    // Took 3.98 GB; the 16 Mi vertices are refused before the accessor is read.
    let r = render(&p, 192, 20);
    assert_refused(&r, &["mesh 0 primitive 0: POSITION accessor 0", "LoadBudget::vertices"]);
}

/// A GLB whose BIN chunk is `bin_len` zero bytes (written sparse), holding one triangle at its start.
fn big_glb(path: &Path, bin_len: u64) {
    let doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin_len}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [0, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    });
    let mut json = serde_json::to_vec(&doc).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() as u64 + 8 + bin_len;
    let mut head = b"glTF".to_vec();
    head.extend(2u32.to_le_bytes());
    head.extend((total as u32).to_le_bytes());
    head.extend((json.len() as u32).to_le_bytes());
    head.extend(b"JSON");
    head.extend(&json);
    head.extend((bin_len as u32).to_le_bytes());
    head.extend(b"BIN\0");
    std::fs::write(path, head).unwrap();
    std::fs::OpenOptions::new().write(true).open(path).unwrap().set_len(total).unwrap();
}

#[test]
fn a_glb_binary_chunk_is_held_once() {
    let _heavy = heavy();
    let d = dir("glb");
    let p = d.join("big.glb");
    // A GLB just under 1 GiB was held three times (3.1 GB): the file, the chunk copied out, a clone per
    // buffer. Held once, 320 MiB fit in 512 MiB of address space; three times would not.
    big_glb(&p, 320 * MIB);
    assert_drawn(&render(&p, 512, 30));
}

#[test]
fn devices_and_fifos_are_refused_without_blocking() {
    assert_refused(&render(Path::new("/dev/zero"), 192, 10), &["/dev/zero", "is a device, not a regular file"]);
    let d = dir("fifo");
    let fifo = d.join("pipe.gltf");
    let made = Command::new("mkfifo").arg(&fifo).status().map(|s| s.success()).unwrap_or(false);
    assert!(made, "mkfifo failed");
    assert_refused(&render(&fifo, 192, 10), &["pipe.gltf", "is a FIFO"]);
    // A buffer naming a FIFO inside the folder.
    let pipe = d.join("data.bin");
    assert!(Command::new("mkfifo").arg(&pipe).status().unwrap().success());
    let mut doc = triangle_doc(json!({}));
    doc["buffers"].as_array_mut().unwrap().push(json!({"byteLength": 4, "uri": "data.bin"}));
    assert_refused(&render(&write_json(&d, "fifo-buffer.gltf", &doc), 192, 10), &["buffer 1", "is a FIFO"]);
}

#[test]
fn play_scene_refuses_what_render_refuses_before_opening_a_window() {
    let d = dir("play");
    let doc = triangle_doc(json!({"cameras": [{"type": "orthographic", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "nodes": [{"camera": 0}]}));
    let p = write_json(&d, "camera.gltf", &doc);
    for (scene, needle) in [(p.to_str().unwrap(), "type is orthographic"), ("/dev/zero", "is a device")] {
        let r = run_bounded(&["play", "--scene", scene], 256, 20);
        assert_refused(&r, &[needle]);
    }
}

// 3. Hangs.

#[test]
fn a_dag_that_places_a_big_mesh_half_a_million_times_is_refused_in_time() {
    // children [k+1, k+1] 19 levels deep: 2^19 placements of a 1 Mi-vertex mesh. It never finished (every
    // visit transformed every vertex for the bounds).
    let d = dir("dag");
    let mut nodes: Vec<Value> = (0..19).map(|k| json!({"children": [k + 1, k + 1]})).collect();
    nodes.push(json!({"mesh": 0}));
    let p = write_json(&d, "dag.gltf", &sparse_doc((1 << 20) - 1, 1, Value::from(nodes), json!([0])));
    let r = render(&p, 512, 30);
    assert_refused(&r, &["vertices after instancing", "LoadBudget::vertices"]);
}

#[test]
fn a_wide_tree_over_a_big_mesh_is_refused_in_time() {
    // A spec-valid tree of 64 Ki leaves over a 64 Ki-vertex mesh took over 30 s.
    let d = dir("tree");
    let leaves = 1usize << 16;
    let mut nodes = vec![json!({"children": (1..257).collect::<Vec<_>>()})];
    for k in 0..256 {
        nodes.push(json!({"children": (257 + k * 256..257 + (k + 1) * 256).collect::<Vec<_>>()}));
    }
    for k in 0..leaves {
        nodes.push(json!({"mesh": 0, "translation": [k % 256, k / 256, 0]}));
    }
    let p = write_json(&d, "tree.gltf", &sparse_doc(leaves as u64 - 1, 1, Value::from(nodes), json!([0])));
    let r = render(&p, 256, 20);
    assert_refused(&r, &["LoadBudget::vertices"]);
}

#[test]
fn a_node_listing_a_million_children_is_charged_before_they_are_pushed() {
    // Node 0 lists node 1 600,000 times and node 1 lists node 2 600,000 times (duplicates pass the crate's
    // validation): 3.6e11 visits. Charged only when popped, the walk's stack held 600,000 entries after one
    // visit and grew by as many per visit (gigabytes); charged when pushed, it is refused at node 1.
    let d = dir("million-children");
    let nodes = json!([
        {"children": vec![1; 600_000]},
        {"children": vec![2; 600_000], "name": "a_LOD0"},
        {"mesh": 0},
    ]);
    let p = write_json(&d, "children.gltf", &sparse_doc(3, 1, nodes, json!([0])));
    let r = render(&p, 256, 30);
    assert_refused(&r, &["node 1's children", "LoadBudget::node_visits"]);
}

#[test]
fn grouping_a_million_named_children_is_linear() {
    // One node lists a million children named like LOD levels ("a_LOD0"): grouping them by name looked up
    // every sibling for every child (10^12 steps). Within the node budget, it loads and renders.
    let d = dir("named-children");
    let nodes = json!([{"children": vec![1; 1_000_000]}, {"name": "a_LOD0"}, {"name": "b_LOD1"}]);
    let p = write_json(&d, "named.gltf", &sparse_doc(3, 1, nodes, json!([0])));
    let r = render(&p, 512, 30);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
}

/// `meshes` meshes, each two primitives (two materials) of 1,500 triangles in the plane z = 0: the second
/// primitive's lie on the first's (decals), or beside them when `overlap` is false (the search then
/// compares every pair).
fn coplanar_doc(meshes: usize, overlap: bool) -> Value {
    let mut pos = vec![];
    for shift in [0.0, if overlap { 0.0 } else { 100.0 }] {
        for k in 0..1500 {
            let (x, y) = ((k % 40) as f32 * 0.1 + shift, (k / 40) as f32 * 0.1);
            pos.extend([x, y, 0.0, x + 0.5, y, 0.0, x, y + 0.5, 0.0]);
        }
    }
    let bytes = f32s(&pos);
    let half = bytes.len() / 2;
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(), "uri": data_uri(&bytes)}],
        "bufferViews": [{"buffer": 0, "byteLength": half}, {"buffer": 0, "byteOffset": half, "byteLength": half}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4500, "type": "VEC3", "min": [0, 0, 0], "max": [4.5, 4.3, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4500, "type": "VEC3", "min": [0, 0, 0], "max": [104.5, 4.3, 0]}],
        "materials": [{}, {}],
        "meshes": (0..meshes).map(|_| json!({"primitives": [
            {"attributes": {"POSITION": 0}, "material": 0}, {"attributes": {"POSITION": 1}, "material": 1}]})).collect::<Vec<_>>(),
        "nodes": (0..meshes).map(|i| json!({"mesh": i, "translation": [0, 0, i as f32 * 0.01]})).collect::<Vec<_>>(),
        "scenes": [{"nodes": (0..meshes).collect::<Vec<_>>()}],
    })
}

#[test]
fn decal_detection_time_does_not_grow_with_the_mesh_count() {
    // 200 meshes of 2 x 1,500 coplanar triangles, none over another: 2.25 M pairs each, capped at 2 M per
    // mesh, took 45 s.
    let d = dir("decals");
    let r = render(&write_json(&d, "coplanar.gltf", &coplanar_doc(200, false)), 512, 20);
    assert_drawn(&r);
}

// 4. Winding under mirroring transforms.

/// Non-background pixels of the single-sided triangle placed with `scale`, seen from +z.
fn pixels_with_scale(d: &Path, name: &str, scale: [f32; 3]) -> usize {
    let doc = triangle_doc(json!({
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100}}],
        "nodes": [{"mesh": 0, "scale": scale}, {"camera": 0, "translation": [0, 0, 3]}],
        "scenes": [{"nodes": [0, 1]}],
    }));
    let p = write_json(d, name, &doc);
    let out = p.with_extension("png");
    let args = [
        "render",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
        "--background",
        "0,0,0",
    ];
    assert_drawn(&run_bounded(&args, 256, 20));
    let (px, _, _) = crate::common::read_png(&out).unwrap();
    px.iter().filter(|&&p| p != 0).count()
}

#[test]
fn a_mirroring_transform_flips_the_front_face() {
    let d = dir("mirror");
    let plain = pixels_with_scale(&d, "plain.gltf", [1.0, 1.0, 1.0]);
    assert!(plain > 100, "the front face is drawn: {plain} pixels");
    // Mirrored in x the triangle still faces the camera (glTF flips the winding with the determinant).
    let x = pixels_with_scale(&d, "mirror-x.gltf", [-1.0, 1.0, 1.0]);
    assert!(x.abs_diff(plain) * 20 < plain, "mirrored in x: {x} pixels, unmirrored {plain}");
    // Point-reflected it faces away: culled.
    assert_eq!(pixels_with_scale(&d, "mirror-xyz.gltf", [-1.0, -1.0, -1.0]), 0);
    // Mirrored twice is not mirrored: scale [-1,-1,1] is a half turn about z, still facing the camera.
    let xy = pixels_with_scale(&d, "mirror-xy.gltf", [-1.0, -1.0, 1.0]);
    assert!(xy.abs_diff(plain) * 20 < plain, "scale [-1,-1,1]: {xy} pixels, unmirrored {plain}");
}

// The loader's bookkeeping, through the library.

fn load(doc: &Value, base: &Path, budget: LoadBudget) -> Result<scanline_racer::asset::LoadedScene, AssetError> {
    load_from_slice_with_budget(&serde_json::to_vec(doc).unwrap(), base, "test.gltf", &budget)
}

fn over(e: AssetError) -> &'static str {
    match e {
        AssetError::Budget { over, .. } => over.limit.field(),
        other => panic!("not a budget error: {other}"),
    }
}

#[test]
fn shared_sources_and_accessors_are_charged_once() {
    let d = dir("charged-once");
    // Buffers: eight names of one 600 KiB file fit in 1 MiB; two files do not.
    sparse_file(&d.join("a.bin"), 600 << 10);
    sparse_file(&d.join("b.bin"), 600 << 10);
    let with = |uris: &[&str]| {
        let mut doc = triangle_doc(json!({}));
        for u in uris {
            doc["buffers"].as_array_mut().unwrap().push(json!({"byteLength": 600 << 10, "uri": u}));
        }
        doc
    };
    let small = LoadBudget { buffer_bytes: MIB, ..LoadBudget::default() };
    load(&with(&["a.bin"; 8]), &d, small).unwrap();
    assert_eq!(over(load(&with(&["a.bin", "b.bin"],), &d, small).unwrap_err()), "buffer_bytes");
    // Images: twelve names of one 8x8 PNG are one texture, charged 64 texels.
    let mut png = vec![];
    image::RgbaImage::from_pixel(8, 8, image::Rgba([255, 0, 0, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    std::fs::write(d.join("red.png"), &png).unwrap();
    std::fs::write(d.join("red2.png"), &png).unwrap();
    let twelve: Vec<String> = vec!["red.png".into(); 12];
    let tiny = LoadBudget { texels: 64, ..LoadBudget::default() };
    let scene = load(&textured_doc(&twelve), &d, tiny).unwrap();
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(scene.meshes.len(), 12);
    assert_eq!(over(load(&textured_doc(&["red.png".into(), "red2.png".into()]), &d, tiny).unwrap_err()), "texels");
    // An accessor of 1,000 VEC3 used by three meshes is read once: 3,000 values.
    let doc = sparse_doc(1000, 3, json!([{"mesh": 0}, {"mesh": 1}, {"mesh": 2}]), json!([0, 1, 2]));
    let values = LoadBudget { accessor_values: 3000, ..LoadBudget::default() };
    assert_eq!(load(&doc, &d, values).unwrap().meshes.len(), 3);
    let fewer = LoadBudget { accessor_values: 2999, ..LoadBudget::default() };
    assert_eq!(over(load(&doc, &d, fewer).unwrap_err()), "accessor_values");
}

#[test]
fn an_honest_big_scene_fits_the_default_budget_and_meshes_are_stored_once() {
    let d = dir("honest");
    // 838 placements of the 5,000-quad grid: 4.19 M polygons, just under the default 4 Mi.
    let scene = load_from_slice(&serde_json::to_vec(&grid_doc(838)).unwrap(), &d, "grid838.gltf").unwrap();
    assert_eq!(scene.meshes.len(), 1, "one mesh however often it is placed");
    assert_eq!(scene.instances.len(), 838);
    assert_eq!(scene.polygon_count(), 838 * 5000);
    let e = load_from_slice(&serde_json::to_vec(&grid_doc(839)).unwrap(), &d, "grid839.gltf").unwrap_err();
    assert_eq!(over(e), "polygons");
    // The bounds come from the mesh's box moved by each placement.
    let (lo, hi) = scene.bounds.unwrap();
    assert_eq!((lo.x, lo.y, hi.z), (0.0, 0.0, 0.0));
    assert!((hi.x - (59.0 * 1.1 + 1.0)).abs() < 1e-4 && (hi.y - (13.0 * 1.1 + 1.0)).abs() < 1e-4, "{hi}");
}

#[test]
fn the_decal_budget_is_shared_by_the_meshes_of_a_load() {
    let d = dir("decal-budget");
    let doc = coplanar_doc(3, true);
    let marked = |budget: LoadBudget| -> Vec<u8> {
        let scene = load(&doc, &d, budget).unwrap();
        scene.meshes.iter().map(|m| m.materials()[1].depth_bias).collect()
    };
    assert_eq!(marked(LoadBudget::default()), [1, 1, 1], "the decals of every mesh are found");
    // A budget that one mesh's search needs: the later meshes are left unmarked.
    let one = LoadBudget { decal_pairs: 1, ..LoadBudget::default() };
    assert_eq!(marked(one), [1, 0, 0]);
    assert_eq!(marked(LoadBudget { decal_pairs: 0, ..LoadBudget::default() }), [0, 0, 0]);
}

#[test]
fn mirrored_placements_share_one_reversed_copy_per_mesh() {
    let d = dir("mirror-copies");
    let mut doc = triangle_doc(json!({}));
    let nodes: Vec<Value> = (0..100)
        .map(|k| json!({"mesh": 0, "scale": if k % 2 == 0 { [-1.0, 1.0, 1.0] } else { [1.0, 1.0, 1.0] }}))
        .collect();
    doc["nodes"] = Value::from(nodes);
    doc["scenes"] = json!([{"nodes": (0..100).collect::<Vec<_>>()}]);
    let scene = load(&doc, &d, LoadBudget::default()).unwrap();
    assert_eq!(scene.meshes.len(), 2, "the mesh and its one reversed copy");
    let idx = |m: usize| scene.meshes[m].polygon_indices(&scene.meshes[m].polygons()[0]).to_vec();
    assert_eq!((idx(0), idx(1)), (vec![0, 1, 2], vec![0, 2, 1]));
    for (k, inst) in scene.instances.iter().enumerate() {
        assert_eq!(inst.mesh, if k % 2 == 0 { 1 } else { 0 });
    }
    // A LOD set (naming convention) under a mirroring parent draws the reversed copies at every level.
    let mut doc = triangle_doc(json!({}));
    doc["meshes"] =
        json!([{"primitives": [{"attributes": {"POSITION": 0}}]}, {"primitives": [{"attributes": {"POSITION": 0}}]}]);
    doc["nodes"] = json!([
        {"scale": [1, 1, -1], "children": [1, 2]},
        {"name": "car_LOD0", "mesh": 0},
        {"name": "car_LOD1", "mesh": 1}]);
    let scene = load(&doc, &d, LoadBudget::default()).unwrap();
    let set = scene.lod_sets[0].meshes;
    for m in set {
        let p = &scene.meshes[m].polygons()[0];
        assert_eq!(scene.meshes[m].polygon_indices(p), [0, 2, 1], "level mesh {m}");
    }
}
