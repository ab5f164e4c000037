//! Golden images: scenes rendered headless and compared with PNGs stored in `tests/golden/`.
//!
//! Threshold: at most 0.1% of pixels may differ by more than 8/255 in any channel (the project's
//! 'wrong pixel' measure). Frames are deterministic, so on this machine the difference is zero; the margin
//! absorbs float differences on other CPUs without hiding a real change (a one-pixel shift of an edge over
//! a whole scene is already several times the threshold). On failure the test writes the actual frame and a
//! difference image and prints where they are. To accept an intended change, regenerate on purpose with
//! `UPDATE_GOLDENS=1 cargo test --test integration golden::` and look at the new PNGs before committing them.

use std::path::{Path, PathBuf};

use crate::common::*;
use scanline_racer::asset::load;
use scanline_racer::render::{Filter, Level, LodMode, Method, RenderOptions, Renderer, TextureMode};

struct Case {
    name: &'static str,
    scene: PathBuf,
    camera: Option<&'static str>,
    options: RenderOptions,
}

fn cases() -> Vec<Case> {
    let court = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf");
    let car = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cars/car_1.gltf");
    let o = |method| RenderOptions { method, threads: 2, ..RenderOptions::default() };
    vec![
        Case { name: "courtyard-zbuffer", scene: court.clone(), camera: Some("eye cam"), options: o(Method::ZBuffer) },
        Case {
            name: "courtyard-bucket-far-256",
            scene: court.clone(),
            camera: Some("0"),
            options: RenderOptions { buckets: 256, ..o(Method::BucketFar) },
        },
        Case {
            name: "courtyard-plan-bucket-near",
            scene: court.clone(),
            camera: Some("plan"),
            options: o(Method::BucketNear),
        },
        Case {
            name: "courtyard-affine",
            scene: court,
            camera: Some("eye cam"),
            options: RenderOptions { texture_mode: TextureMode::Affine, ..o(Method::ZBuffer) },
        },
        Case {
            name: "duck-bilinear",
            scene: samples().join("Duck/Duck.gltf"),
            camera: None,
            options: RenderOptions { filter: Filter::Bilinear, ..o(Method::ZBuffer) },
        },
        Case {
            name: "engine-sort",
            scene: samples().join("2CylinderEngine/2CylinderEngine.gltf"),
            camera: None,
            options: o(Method::Sort),
        },
        Case {
            name: "avocado-subdivided",
            scene: samples().join("Avocado/Avocado.gltf"),
            camera: None,
            options: RenderOptions { texture_mode: TextureMode::Subdivided, ..o(Method::BucketFar) },
        },
        Case {
            name: "box-vertex-colors",
            scene: samples().join("BoxVertexColors.gltf"),
            camera: None,
            options: o(Method::BucketNear),
        },
        Case {
            name: "car-close",
            scene: car.clone(),
            camera: Some("front"),
            options: RenderOptions { lod: LodMode::Force(Level::Close), ..o(Method::ZBuffer) },
        },
        Case {
            name: "car-mid",
            scene: car.clone(),
            camera: Some("front"),
            options: RenderOptions { lod: LodMode::Force(Level::Mid), ..o(Method::BucketFar) },
        },
        Case {
            name: "car-long",
            scene: car,
            camera: Some("front"),
            options: RenderOptions { lod: LodMode::Force(Level::Long), ..o(Method::BucketNear) },
        },
    ]
}

#[test]
fn scenes_match_their_golden_images() {
    let (w, h) = (320usize, 240usize);
    let update = std::env::var_os("UPDATE_GOLDENS").is_some();
    assert!(!(update && std::env::var_os("CI").is_some()), "UPDATE_GOLDENS is for people, not CI");
    let golden_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let fail_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/golden-failures");
    let mut failures = vec![];
    for case in cases() {
        let scene = load(&case.scene).unwrap_or_else(|e| panic!("{e}"));
        let camera = match case.camera {
            Some(sel) => scene.find_camera(sel).unwrap_or_else(|| panic!("{}: no camera {sel}", case.name)).camera,
            None => scene.framing_camera(w as f32 / h as f32),
        };
        let mut frame = vec![0u32; w * h];
        Renderer::new().render(&mut frame, w, h, &camera, &scene.draw_list(), &case.options).unwrap();
        let golden_path = golden_dir.join(format!("{}.png", case.name));
        if update {
            write_png(&golden_path, &frame, w, h);
            eprintln!("updated {}", golden_path.display());
            continue;
        }
        let Some((golden, gw, gh)) = read_png(&golden_path) else {
            failures.push(format!("{}: golden {} is missing or unreadable", case.name, golden_path.display()));
            continue;
        };
        assert_eq!((gw, gh), (w, h), "{}: golden size", case.name);
        let wrong = frame.iter().zip(&golden).filter(|(a, b)| channel_diff(**a, **b) > 8).count();
        // 0.1% of the frame.
        if wrong * 1000 > w * h {
            let actual = fail_dir.join(format!("{}.actual.png", case.name));
            let diff_path = fail_dir.join(format!("{}.diff.png", case.name));
            write_png(&actual, &frame, w, h);
            let diff: Vec<u32> = frame
                .iter()
                .zip(&golden)
                .map(|(a, b)| if channel_diff(*a, *b) > 8 { 0xff00ff } else { (b >> 2) & 0x3f3f3f })
                .collect();
            write_png(&diff_path, &diff, w, h);
            failures.push(format!(
                "{}: {wrong} of {} pixels differ by more than 8/255 (threshold 0.1%)\n  golden: {}\n  actual: {}\n  diff (magenta = wrong): {}",
                case.name,
                w * h,
                golden_path.display(),
                actual.display(),
                diff_path.display()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{}\nIf the change is intended, regenerate with: UPDATE_GOLDENS=1 cargo test --test integration golden:: (then look at tests/golden/*.png)",
        failures.join("\n")
    );
}
