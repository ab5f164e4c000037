//! The `render` command end to end: output, statistics JSON, exit codes and one-line errors on bad input,
//! including hostile glTF files.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::*;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    c.env("SCANLINE_RACER_RECORDS", Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"));
    c
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("run scanline-racer")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts a failure with the given status and a single-line error that mentions `needle`.
fn assert_one_line_error(o: &Output, status: i32, needle: &str) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(status), "stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    if status == 1 {
        assert_eq!(err.trim_end().lines().count(), 1, "expected one line, got: {err}");
    }
    assert!(err.to_lowercase().contains(&needle.to_lowercase()), "expected '{needle}' in: {err}");
}

#[test]
fn render_writes_png_and_json_stats() {
    let out = tmp("duck.png");
    let scene = samples().join("Duck/Duck.gltf");
    let o = run(&[
        "render",
        scene.to_str().unwrap(),
        "--width",
        "200",
        "--height",
        "150",
        "--method",
        "bucket-near",
        "--buckets",
        "64",
        "--key",
        "min",
        "--repeat",
        "3",
        "--threads",
        "2",
        "--out",
        out.to_str().unwrap(),
        "--stats",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("stdout is one JSON object");
    assert_eq!(v["method"], "bucket-near");
    assert_eq!(v["width"], 200);
    assert_eq!(v["height"], 150);
    assert_eq!(v["frames"], 3);
    assert_eq!(v["buckets"], 64);
    assert_eq!(v["key"], "min");
    assert_eq!(v["polygons_in"], 4212);
    for k in
        ["ms_median", "ms_min", "polygons_drawn", "pixels_written", "ms_transform", "ms_clip", "ms_order", "ms_fill"]
    {
        assert!(v[k].is_number(), "{k} missing in {v}");
    }
    assert!(v["ms_min"].as_f64() <= v["ms_median"].as_f64());
    let (px, w, h) = read_png(&out).expect("PNG written");
    assert_eq!((w, h), (200, 150));
    // The duck is yellow-ish and covers pixels_written pixels; everything else is the sky-blue background.
    let not_bg = px.iter().filter(|&&p| p != 0x87ceeb).count() as u64;
    assert_eq!(Some(not_bg), v["pixels_written"].as_u64());
}

#[test]
fn background_camera_and_methods_on_the_command_line() {
    let out = tmp("court.png");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf");
    for method in ["zbuffer", "sort", "bucket-far", "bucket-near"] {
        let o = run(&[
            "render",
            scene.to_str().unwrap(),
            "--camera",
            "plan",
            "--method",
            method,
            "--background",
            "1,2,3",
            "--width",
            "64",
            "--height",
            "48",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{method}: {}", stderr(&o));
    }
    let o = run(&[
        "render",
        scene.to_str().unwrap(),
        "--camera",
        "eye cam",
        "--background",
        "1,2,3",
        "--width",
        "64",
        "--height",
        "48",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let (px, _, _) = read_png(&out).unwrap();
    assert_eq!(px[0], 0x010203, "the sky is the requested background");
}

#[test]
fn bad_input_gives_one_line_errors() {
    let out = tmp("x.png");
    let o = out.to_str().unwrap();
    let court = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf");
    let c = court.to_str().unwrap();
    assert_one_line_error(&run(&["render", "/no/such/file.gltf", "--out", o]), 1, "cannot read");
    assert_one_line_error(&run(&["render", c, "--camera", "7", "--out", o]), 1, "no camera '7'");
    assert_one_line_error(&run(&["render", c, "--camera", "nobody", "--out", o]), 1, "no camera 'nobody'");
    assert_one_line_error(&run(&["render", c, "--method", "raytrace", "--out", o]), 2, "raytrace");
    assert_one_line_error(&run(&["render", c, "--background", "300,0,0", "--out", o]), 2, "background");
    assert_one_line_error(&run(&["render", c, "--width", "0", "--out", o]), 2, "width");
    assert_one_line_error(&run(&["render", c, "--out", "/no/such/dir/x.png"]), 1, "cannot write");
    assert_one_line_error(&run(&["frobnicate"]), 2, "frobnicate");
}

/// Writes a glTF file built from the courtyard's JSON with one change, and returns its path.
fn mutated(name: &str, f: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let src =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&src).unwrap();
    f(&mut v);
    let p = tmp(name);
    std::fs::write(&p, serde_json::to_vec(&v).unwrap()).unwrap();
    p
}

#[test]
fn hostile_and_broken_gltf_files_are_refused_without_panic() {
    let out = tmp("hostile.png");
    let o = out.to_str().unwrap();
    let cases: Vec<(PathBuf, &str)> = vec![
        (mutated("escape.gltf", |v| v["buffers"][0]["uri"] = "../../../etc/passwd".into()), "refused"),
        (mutated("absolute.gltf", |v| v["buffers"][0]["uri"] = "/etc/passwd".into()), "refused"),
        (mutated("scheme.gltf", |v| v["buffers"][0]["uri"] = "http://example.com/x.bin".into()), "refused"),
        (mutated("short.gltf", |v| v["buffers"][0]["byteLength"] = 1_000_000_000u64.into()), "byteLength"),
        (mutated("count.gltf", |v| v["accessors"][0]["count"] = 4_000_000_000u64.into()), "accessor"),
        (mutated("offset.gltf", |v| v["accessors"][1]["byteOffset"] = 1_000_000u64.into()), "mesh"),
        (mutated("view.gltf", |v| v["bufferViews"][1]["byteOffset"] = 100_000u64.into()), "buffer view"),
        (
            mutated("image.gltf", |v| v["images"][0]["uri"] = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUg==".into()),
            "image 0",
        ),
        (mutated("noimage.gltf", |v| v["images"][0]["uri"] = "missing.png".into()), "image 0"),
        (mutated("cycle.gltf", |v| v["nodes"][0]["children"] = serde_json::json!([8])), "node"),
        (mutated("badindex.gltf", |v| v["meshes"][0]["primitives"][0]["indices"] = 9999.into()), "valid glTF"),
        (mutated("camera.gltf", |v| v["cameras"][0]["perspective"]["yfov"] = (-1.0).into()), "camera"),
        (
            mutated("required.gltf", |v| v["extensionsRequired"] = serde_json::json!(["KHR_draco_mesh_compression"])),
            "glTF",
        ),
    ];
    for (path, needle) in &cases {
        let r = run(&["render", path.to_str().unwrap(), "--out", o]);
        assert_one_line_error(&r, 1, needle);
        assert!(
            stderr(&r).contains(path.file_name().unwrap().to_str().unwrap()),
            "error names the file: {}",
            stderr(&r)
        );
    }
    // Garbage bytes, an empty file, a truncated GLB.
    for (name, bytes) in [
        ("garbage.gltf", b"{not json".to_vec()),
        ("empty.glb", vec![]),
        ("trunc.glb", b"glTF\x02\x00\x00\x00\xff\xff\x00\x00".to_vec()),
    ] {
        let p = tmp(name);
        std::fs::write(&p, bytes).unwrap();
        assert_one_line_error(&run(&["render", p.to_str().unwrap(), "--out", o]), 1, "not a valid glTF");
    }
}

#[test]
fn indices_out_of_range_are_reported() {
    // Make the courtyard's first index buffer point past the vertex count by lowering POSITION's count.
    let p = mutated("fewverts.gltf", |v| {
        for attr in ["POSITION", "TEXCOORD_0"] {
            let a = v["meshes"][0]["primitives"][0]["attributes"][attr].as_u64().unwrap() as usize;
            v["accessors"][a]["count"] = 2.into();
        }
    });
    let out = tmp("few.png");
    let r = run(&["render", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_one_line_error(&r, 1, "out of range");
}

/// Packs the courtyard into a GLB: one BIN chunk holding the buffer and every image (as buffer views).
fn courtyard_glb() -> Vec<u8> {
    use base64::Engine;
    let src =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&src).unwrap();
    let decode = |uri: &str| base64::engine::general_purpose::STANDARD.decode(uri.split_once(',').unwrap().1).unwrap();
    let mut bin = decode(v["buffers"][0]["uri"].as_str().unwrap());
    let images = v["images"].as_array().unwrap().clone();
    for (i, img) in images.iter().enumerate() {
        let bytes = decode(img["uri"].as_str().unwrap());
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let view = v["bufferViews"].as_array().unwrap().len();
        v["bufferViews"]
            .as_array_mut()
            .unwrap()
            .push(serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend_from_slice(&bytes);
        v["images"][i] = serde_json::json!({"bufferView": view, "mimeType": "image/png"});
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    v["buffers"][0] = serde_json::json!({"byteLength": bin.len()});
    let mut json = serde_json::to_vec(&v).unwrap();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    glb
}

#[test]
fn glb_with_embedded_images_renders_like_the_gltf() {
    let glb = tmp("courtyard.glb");
    std::fs::write(&glb, courtyard_glb()).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf");
    let (a, b) = (tmp("from-gltf.png"), tmp("from-glb.png"));
    for (input, out) in [(&scene, &a), (&glb, &b)] {
        let o = run(&[
            "render",
            input.to_str().unwrap(),
            "--camera",
            "eye cam",
            "--width",
            "160",
            "--height",
            "120",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let (pa, _, _) = read_png(&a).unwrap();
    let (pb, _, _) = read_png(&b).unwrap();
    assert!(pa == pb, "GLB and glTF frames differ");
    // A GLB cut short anywhere is refused in one line, never a panic.
    let bytes = courtyard_glb();
    for cut in [0, 11, 12, 20, 100, bytes.len() / 2, bytes.len() - 1] {
        let p = tmp("cut.glb");
        std::fs::write(&p, &bytes[..cut]).unwrap();
        let r = run(&["render", p.to_str().unwrap(), "--out", tmp("cut.png").to_str().unwrap()]);
        assert_eq!(r.status.code(), Some(1), "cut at {cut}: {}", stderr(&r));
        assert_eq!(stderr(&r).trim_end().lines().count(), 1, "cut at {cut}: {}", stderr(&r));
    }
}

/// `bench --quick` measures every course's demo race: one CSV with a course column and three charts per
/// course; the z-buffer has no visibility error, every method and the view-lists levels are there, a
/// Pareto front is marked, the stability measures are numbers, and only the automatic LOD choice pops.
#[test]
fn bench_quick_writes_csv_and_charts() {
    let out = tmp("bench");
    let _ = std::fs::remove_dir_all(&out);
    let o = run(&["bench", "--quick", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(out.join("bench.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() >= 75, "{} rows", rows.len());
    for course in ["circuit", "city", "mountain"] {
        let of: Vec<&Vec<&str>> = rows.iter().filter(|r| r[col("course")] == course).collect();
        assert!(of.len() >= 25, "{course}: {} rows", of.len());
        for m in ["zbuffer", "sort", "bucket-far", "bucket-near", "view-lists"] {
            assert!(of.iter().any(|r| r[col("method")] == m), "{course}: {m} missing");
        }
    }
    let zb = rows.iter().find(|r| r[col("label")] == "zbuffer").unwrap();
    assert_eq!(zb[col("vis_wrong_pct")].parse::<f64>().unwrap(), 0.0);
    assert!(rows.iter().any(|r| r[col("pareto")] == "true"));
    assert!(rows.iter().all(|r| r[col("ms_median")].parse::<f64>().unwrap() > 0.0));
    let number = |r: &Vec<&str>, name: &str| r[col(name)].parse::<f64>().unwrap_or_else(|e| panic!("{name}: {e}"));
    for r in &rows {
        assert_eq!(r.len(), header.len());
        for name in ["seq_flip_mean", "shimmer_rms", "shimmer_pct", "lod_pops_per_min"] {
            assert!(number(r, name).is_finite() && number(r, name) >= 0.0, "{name} in {r:?}");
        }
        if r[col("lod")] != "auto" {
            assert_eq!(number(r, "lod_pops_per_min"), 0.0, "{r:?}");
        }
    }
    assert!(number(zb, "shimmer_rms") > 0.0 && number(zb, "lod_pops_per_min") > 0.0);
    assert!(rows.iter().any(|r| r[col("stability_pareto")] == "true"));
    for chart in ["bench", "visibility", "stability"].iter().flat_map(|c| [format!("{c}-circuit"), format!("{c}-city")])
    {
        let (px, w, h) = read_png(&out.join(format!("{chart}.png"))).unwrap();
        assert_eq!((w, h), (1200, 760));
        assert!(px.iter().filter(|&&p| p != 0xffffff).count() > 5000, "{chart}.png has a plot");
        let svg = std::fs::read_to_string(out.join(format!("{chart}.svg"))).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("Pareto front"));
    }
    // One course, by name: its rows only.
    let one = tmp("bench-city");
    let _ = std::fs::remove_dir_all(&one);
    let o = run(&["bench", "--quick", "--course", "city", "--out", one.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(one.join("bench.csv")).unwrap();
    assert!(csv.lines().skip(1).all(|l| l.starts_with("city,")), "{csv}");
    assert!(one.join("bench-city.png").is_file() && !one.join("bench-circuit.png").exists());
}

/// `export-frame` writes a GLB that any glTF reader opens, and drawing it from its own camera gives the
/// frame the replay draws at that tick (the same triangles after LOD; measured 0.3% of pixels differ,
/// where fanned polygons meet and at the LOD choice).
#[test]
fn export_frame_writes_the_frame_as_glb() {
    let glb = tmp("frame-1500.glb");
    let trace = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/replays/demo-race.trace");
    let o = run(&[
        "export-frame",
        trace.to_str().unwrap(),
        "--tick",
        "1500",
        "--width",
        "320",
        "--height",
        "180",
        "--out",
        glb.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&glb).unwrap();
    let g = gltf::Gltf::from_slice(&bytes).expect("a valid GLB");
    assert_eq!(g.cameras().count(), 1);
    assert!(g.meshes().next().unwrap().primitives().count() > 5);
    let png = tmp("frame-1500.png");
    let r = run(&[
        "render",
        glb.to_str().unwrap(),
        "--camera",
        "frame camera",
        "--width",
        "320",
        "--height",
        "180",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    let frames = tmp("frames-1500");
    let _ = std::fs::remove_dir_all(&frames);
    let f = run(&[
        "replay",
        trace.to_str().unwrap(),
        "--headless",
        "--frames",
        frames.to_str().unwrap(),
        "--every",
        "1500",
        "--width",
        "320",
        "--height",
        "180",
    ]);
    assert!(f.status.success(), "{}", stderr(&f));
    let (a, _, _) = read_png(&png).unwrap();
    let (b, _, _) = read_png(&frames.join("frame_001500.png")).unwrap();
    let wrong = a.iter().zip(&b).filter(|(p, q)| channel_diff(**p, **q) > 8).count();
    assert!(wrong * 100 < a.len(), "{wrong} of {} pixels differ", a.len());
    // A tick past the end of the trace is one line.
    let late = run(&["export-frame", trace.to_str().unwrap(), "--tick", "999999", "--out", glb.to_str().unwrap()]);
    assert_one_line_error(&late, 1, "ends at tick");
}

/// `courses` lists every course with its lap length and title; `play --course` refuses a name that is not
/// a folder name with usage (exit 2) before any window opens.
#[test]
fn courses_lists_every_course_and_play_refuses_a_bad_course_name() {
    let o = bin()
        .arg("courses")
        .env("SCANLINE_RACER_ASSETS", Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    assert!(
        lines[0].starts_with("circuit ") && lines[0].contains("4.16 km") && lines[0].contains("Green Valley Circuit"),
        "{text}"
    );
    assert!(lines[1].starts_with("city ") && lines[1].contains("Harbour Streets"), "{text}");
    assert!(
        lines[2].starts_with("mountain ") && lines[2].contains("5.75 km") && lines[2].contains("Eagle Pass"),
        "{text}"
    );
    let o = run(&["play", "--course", "../track", "--exit-after-frames", "1"]);
    assert_one_line_error(&o, 2, "a course is named by its folder");
}
