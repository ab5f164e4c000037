//! Valid glTF 2.0 that the `gltf` crate's validation refused is loaded as the specification says, and a
//! URI is refused only for what it really breaks: an accessor without a `bufferView` is zeros (under its
//! sparse values, if any) and draws exactly what the same file with the zeros written out draws; a path
//! whose `..` stays inside the asset's folder is read; a NUL byte is named as such.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use base64::Engine;
use serde_json::{Value, json};

use crate::common::*;

fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("conformance").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(bytes))
}

fn f32s(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A triangle with black vertex colours: `accessors` are POSITION (0) and COLOR_0 (1) over `buffers` and
/// `views`.
fn doc(buffers: Value, views: Value, accessors: Value) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "buffers": buffers,
        "bufferViews": views,
        "accessors": accessors,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
    })
}

fn render(scene: &Path, out: &Path) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    c.arg("render").arg(scene).arg("--out").arg(out).args(["--width", "64", "--height", "48"]);
    run_bounded(&mut c, 60, "render")
}

fn rendered(scene: &Path, out: &Path) -> Vec<u32> {
    let o = render(scene, out);
    assert!(o.status.success(), "{}: {}", scene.display(), String::from_utf8_lossy(&o.stderr));
    read_png(out).unwrap().0
}

#[test]
fn accessors_without_a_buffer_view_are_zeros_under_their_sparse_values() {
    let d = folder("zeros");
    let (min, max) = (json!([0, 0, 0]), json!([1, 1, 0]));
    // Written out: three positions, and nine zero colour components.
    let mut bytes = f32s(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    bytes.extend(f32s(&[0.; 9]));
    let explicit = doc(
        json!([{"byteLength": 72, "uri": data_uri(&bytes)}]),
        json!([{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}]),
        json!([
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": min, "max": max},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
        ]),
    );
    // Implicit: vertex 0 is the zero every element starts as, vertices 1 and 2 are sparse values, and the
    // colours have neither a view nor sparse values.
    let mut sparse = [1u16, 2].iter().flat_map(|i| i.to_le_bytes()).collect::<Vec<u8>>();
    sparse.extend(f32s(&[1., 0., 0., 0., 1., 0.]));
    let implicit = doc(
        json!([{"byteLength": 28, "uri": data_uri(&sparse)}]),
        json!([{"buffer": 0, "byteLength": 4}, {"buffer": 0, "byteOffset": 4, "byteLength": 24}]),
        json!([
            {"componentType": 5126, "count": 3, "type": "VEC3", "min": min, "max": max,
             "sparse": {"count": 2, "indices": {"bufferView": 0, "componentType": 5123},
                        "values": {"bufferView": 1}}},
            {"componentType": 5126, "count": 3, "type": "VEC3"},
        ]),
    );
    let write = |name: &str, v: &Value| {
        let p = d.join(name);
        std::fs::write(&p, serde_json::to_vec(v).unwrap()).unwrap();
        p
    };
    let a = rendered(&write("explicit.gltf", &explicit), &d.join("explicit.png"));
    let b = rendered(&write("implicit.gltf", &implicit), &d.join("implicit.png"));
    let black = a.iter().filter(|&&p| p == 0).count();
    assert!(black > 200, "the black triangle covers {black} pixels");
    assert!(a == b, "the zero-filled accessors draw what the written-out zeros draw");
}

#[test]
fn a_uri_is_refused_only_for_what_it_breaks() {
    let d = folder("uris");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    let mut bytes = f32s(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    bytes.extend(f32s(&[0.; 9]));
    std::fs::write(d.join("tri.bin"), &bytes).unwrap();
    let scene = |name: &str, uri: &str| {
        let v = doc(
            json!([{"byteLength": 72, "uri": uri}]),
            json!([{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}]),
            json!([
                {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
            ]),
        );
        let p = d.join(name);
        std::fs::write(&p, serde_json::to_vec(&v).unwrap()).unwrap();
        p
    };
    let plain = rendered(&scene("plain.gltf", "tri.bin"), &d.join("plain.png"));
    let inside = rendered(&scene("inside.gltf", "sub/../tri.bin"), &d.join("inside.png"));
    assert!(plain == inside, "sub/../tri.bin is tri.bin");
    for (uri, why) in [
        ("tri%00.bin", "it holds a NUL byte (%00), which no file name may hold"),
        ("sub/../../tri.bin", "its '..' parts climb above the asset's folder"),
        ("", "the URI is empty"),
        ("ftp://host/tri.bin", "the scheme 'ftp:' is not read: only data: URIs and relative paths are"),
    ] {
        let file = scene("refused.gltf", uri);
        let o = render(&file, &d.join("refused.png"));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{uri}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{uri}: {err}");
        assert!(err.trim_end().ends_with(&format!("URI '{uri}' refused: {why}")), "{uri}: {err}");
    }
}
