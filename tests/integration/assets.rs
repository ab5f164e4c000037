//! The shipped assets: generated deterministically, within the seed's polygon and texel budgets, with levels
//! of detail chosen by projected size, with hysteresis, and measured against the all-close reference.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::common::files_under;
use glam::Vec3;
use scanline_racer::asset::{LoadedScene, load};
use scanline_racer::render::{Camera, Level, LodMode, RenderOptions, Renderer};

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets")
}

fn generate(into: &Path) {
    let _ = std::fs::remove_dir_all(into);
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_assetgen")).arg(into).status().unwrap();
    assert!(st.success());
}

#[test]
fn committed_assets_are_exactly_what_the_generator_makes() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let (a, b) = (tmp.join("assets-a"), tmp.join("assets-b"));
    generate(&a);
    generate(&b);
    let (fa, fb, committed) = (files_under(&a), files_under(&b), files_under(&assets()));
    assert!(fa == fb, "two runs of the generator differ");
    let names = |m: &BTreeMap<PathBuf, Vec<u8>>| m.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&committed), names(&fa), "committed files differ from generated ones");
    let stale: Vec<_> =
        fa.iter().filter(|(k, v)| committed.get(*k) != Some(*v)).map(|(k, _)| k.display().to_string()).collect();
    assert!(stale.is_empty(), "stale assets {stale:?}: regenerate with `cargo run --release --bin assetgen`");
    let total: usize = committed.values().map(Vec::len).sum();
    // Three courses, the mountain's thousands of trees and boulders as LOD nodes among them: 11 MB.
    assert!(total < 12 << 20, "assets/ is {total} bytes, over 12 MB");
}

fn car_files() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(assets().join("cars"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gltf"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_car_has_three_levels_in_the_seed_ranges_with_matching_textures() {
    let cars = car_files();
    assert!(cars.len() >= 8, "only {} cars", cars.len());
    let mut atlases = vec![];
    for path in &cars {
        let scene = load(path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.lod_sets.len(), 1, "{}: one LOD set", path.display());
        let set = scene.lod_sets[0];
        let polys = set.meshes.map(|m| scene.meshes[m].polygons().len());
        assert!((200..=300).contains(&polys[0]), "{}: close model has {} polygons", path.display(), polys[0]);
        assert!((20..=30).contains(&polys[1]), "{}: mid model has {} polygons", path.display(), polys[1]);
        assert_eq!(polys[2], 6, "{}: long model is a hexahedron", path.display());
        // Texture resolution per level: every texture a level uses, by (width, height).
        let sizes = set.meshes.map(|m| {
            let mut s: Vec<(u32, u32)> = scene.meshes[m]
                .materials()
                .iter()
                .filter_map(|mat| mat.texture.map(|t| (scene.textures[t].width(), scene.textures[t].height())))
                .collect();
            s.sort();
            s.dedup();
            s
        });
        assert_eq!(sizes[0], [(128, 128), (256, 256)], "{}: close atlas and detail texture", path.display());
        assert_eq!(sizes[1], [(64, 64)], "{}", path.display());
        assert_eq!(sizes[2], [(16, 16)], "{}", path.display());
        // The sharp parts (detail texture) get more texels per metre than the body atlas.
        let close = &scene.meshes[set.meshes[0]];
        let density = |material_size: u32| -> f32 {
            let mut best = 0.0f32;
            for p in close.polygons() {
                let mat = &close.materials()[p.material as usize];
                let Some(t) = mat.texture else { continue };
                if scene.textures[t].width() != material_size {
                    continue;
                }
                let idx = close.polygon_indices(p);
                let (a, b) = (close.vertices()[idx[0] as usize], close.vertices()[idx[1] as usize]);
                let metres = (b.position - a.position).length();
                let texels = ((b.uv - a.uv) * material_size as f32).length();
                if metres > 0.05 {
                    best = best.max(texels / metres);
                }
            }
            best
        };
        assert!(density(128) > 2.0 * density(256), "{}: detail parts are not sharper", path.display());
        atlases.push(scene.textures.iter().find(|t| t.width() == 256).unwrap().texels().to_vec());
    }
    for i in 0..atlases.len() {
        for j in i + 1..atlases.len() {
            assert!(atlases[i] != atlases[j], "cars {i} and {j} share a livery");
        }
    }
}

/// Renders one car alone at `distance` in front of a camera with a 0.8 rad field of view, and returns the
/// level the renderer chose.
fn level_at(scene: &LoadedScene, renderer: &mut Renderer, distance: f32, height: usize, bias: f32) -> Level {
    let camera = Camera::look_at(Vec3::new(0.0, 0.6, distance), Vec3::new(0.0, 0.6, 0.0), 0.8, 0.1, None);
    let list = scene.draw_list();
    let mut frame = vec![0u32; 8 * height];
    let opts = RenderOptions { lod_bias: bias, threads: 1, ..RenderOptions::default() };
    let s = renderer.render(&mut frame, 8, height, &camera, &list, &opts).unwrap();
    assert_eq!(s.lod_close + s.lod_mid + s.lod_long, 1);
    if s.lod_close == 1 {
        Level::Close
    } else if s.lod_mid == 1 {
        Level::Mid
    } else {
        Level::Long
    }
}

#[test]
fn selection_by_projected_size_at_known_distances_and_resolutions() {
    let scene = load(&assets().join("cars/car_1.gltf")).unwrap();
    let set = scene.lod_sets[0];
    let [close_px, long_px] = set.switch_px;
    assert!(
        (close_px - 100.0).abs() < 0.01 && (long_px - 25.0).abs() < 0.01,
        "car files ask for 100 and 25 pixels at 720 lines: {:?}",
        set.switch_px
    );
    let radius = scene.meshes[set.meshes[0]].bounds().radius;
    // Projected height of the bounding sphere: radius * cot(fov / 2) * height / distance.
    let cot = 1.0 / libm::tanf(0.4f32);
    let distance_for = |px: f32, height: usize| radius * cot * height as f32 / px;
    for height in [240usize, 720, 1440] {
        for (px, expect) in [
            (300.0, Level::Close),
            (101.0, Level::Close),
            (99.0, Level::Mid),
            (26.0, Level::Mid),
            (24.0, Level::Long),
            (5.0, Level::Long),
        ] {
            let mut r = Renderer::new();
            assert_eq!(
                level_at(&scene, &mut r, distance_for(px, height), height, 0.0),
                expect,
                "{px} px at {height} lines"
            );
        }
    }
    // The same distance gives a finer level on a taller frame, and a positive bias keeps the finer level.
    let d = distance_for(60.0, 720);
    assert_eq!(level_at(&scene, &mut Renderer::new(), d, 720, 0.0), Level::Mid);
    assert_eq!(level_at(&scene, &mut Renderer::new(), d, 1440, 0.0), Level::Close);
    assert_eq!(level_at(&scene, &mut Renderer::new(), d, 240, 0.0), Level::Long);
    assert_eq!(level_at(&scene, &mut Renderer::new(), d, 720, 1.0), Level::Close);
    assert_eq!(level_at(&scene, &mut Renderer::new(), d, 720, -2.0), Level::Long);
}

#[test]
fn a_slow_approach_and_retreat_switch_once_each_way() {
    let scene = load(&assets().join("cars/car_3.gltf")).unwrap();
    let mut r = Renderer::new();
    let mut last = None;
    let mut switches = vec![];
    // From 200 m in to 5 m and back out, with a small jitter at every step (a car bobbing on the road).
    let steps: Vec<f32> = (0..800)
        .map(|i| {
            let t = if i < 400 { i as f32 / 400.0 } else { (800 - i) as f32 / 400.0 };
            let d = 200.0 * libm::powf(5.0f32 / 200.0, t);
            d * (1.0 + 0.04 * libm::sinf(i as f32 * 1.3))
        })
        .collect();
    for d in steps {
        let l = level_at(&scene, &mut r, d, 720, 0.0);
        if last.is_some_and(|p| p != l) {
            switches.push(l);
        }
        last = Some(l);
    }
    assert_eq!(switches, [Level::Mid, Level::Close, Level::Mid, Level::Long]);
}

#[test]
fn forced_levels_report_that_levels_polygons() {
    let path = assets().join("cars/car_2.gltf");
    let scene = load(&path).unwrap();
    let set = scene.lod_sets[0];
    let camera = Camera::look_at(Vec3::new(3.0, 2.0, 6.0), Vec3::ZERO, 0.8, 0.1, None);
    for (mode, level) in
        [(LodMode::Force(Level::Close), 0), (LodMode::Force(Level::Mid), 1), (LodMode::Force(Level::Long), 2)]
    {
        let mut frame = vec![0u32; 64 * 48];
        let opts = RenderOptions { lod: mode, ..RenderOptions::default() };
        let s = Renderer::new().render(&mut frame, 64, 48, &camera, &scene.draw_list(), &opts).unwrap();
        assert_eq!(s.polygons_in as usize, scene.meshes[set.meshes[level]].polygons().len());
        let saved = scene.meshes[set.meshes[0]].polygons().len() - scene.meshes[set.meshes[level]].polygons().len();
        assert_eq!(s.polygons_saved_by_lod as usize, saved);
    }
}

fn centerline() -> (f64, Vec<([f64; 3], f64)>) {
    let text = std::fs::read_to_string(assets().join("track/circuit/centerline.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let samples = v["samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let p = s["p"].as_array().unwrap();
            ([p[0].as_f64().unwrap(), p[1].as_f64().unwrap(), p[2].as_f64().unwrap()], s["bank"].as_f64().unwrap())
        })
        .collect();
    (v["length_m"].as_f64().unwrap(), samples)
}

#[test]
fn the_circuit_is_closed_crosses_itself_and_has_straights_corners_hills_and_banking() {
    let (length, s) = centerline();
    let n = s.len();
    assert!((3000.0..=5000.0).contains(&length), "length {length} m");
    let horiz = |a: [f64; 3], b: [f64; 3]| ((a[0] - b[0]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    assert!(horiz(s[0].0, s[n - 1].0) < 15.0, "the loop closes");
    // A crossing: two samples far apart along the track, nearly on top of each other, 6 m or more apart in height.
    let mut crossing = None;
    for i in 0..n {
        for j in i + 60..n.saturating_sub(60).max(i + 60) {
            if horiz(s[i].0, s[j].0) < 6.0 && (s[i].0[1] - s[j].0[1]).abs() >= 6.0 {
                crossing = Some((i, j));
            }
        }
    }
    assert!(crossing.is_some(), "no place where the track passes over itself");
    let heights: Vec<f64> = s.iter().map(|x| x.0[1]).collect();
    let (lo, hi) = heights.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &y| (l.min(y), h.max(y)));
    assert!(hi - lo >= 5.0, "elevation range {lo}..{hi}");
    let max_bank = s.iter().map(|x| x.1.abs()).fold(0.0, f64::max);
    assert!(max_bank >= 0.08, "banking up to {max_bank} rad");
    // Heading change per sample gives the local radius of curvature.
    let heading: Vec<f64> = (0..n)
        .map(|i| {
            let (a, b) = (s[i].0, s[(i + 1) % n].0);
            libm::atan2(b[2] - a[2], b[0] - a[0])
        })
        .collect();
    let turn = |i: usize| {
        let d = heading[(i + 1) % n] - heading[i];
        (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    let step = length / n as f64;
    let radius: Vec<f64> = (0..n).map(|i| step / turn(i).abs().max(1e-9)).collect();
    let min_radius = radius.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(min_radius <= 50.0, "tightest corner radius {min_radius} m");
    let mut longest_straight = 0.0f64;
    let mut run = 0.0;
    let mut fast_corner = false;
    let mut fast_run = 0.0;
    // Twice round, so a straight through the start line counts whole.
    for r in radius.iter().chain(&radius) {
        run = if *r > 2000.0 { run + step } else { 0.0 };
        longest_straight = longest_straight.max(run);
        fast_run = if (120.0..=400.0).contains(r) { fast_run + step } else { 0.0 };
        fast_corner |= fast_run >= 80.0;
    }
    assert!(longest_straight >= 600.0, "longest straight {longest_straight} m");
    assert!(fast_corner, "no fast corner of radius 120-400 m over 80 m");
}

#[test]
fn the_circuit_scene_has_its_furniture_and_stays_within_budget() {
    let scene = load(&assets().join("track/circuit/circuit.gltf")).unwrap();
    let polys = scene.polygon_count();
    assert!((5_000..=40_000).contains(&polys), "{polys} polygons");
    assert!(scene.lod_sets.len() >= 100, "trees are LOD sets: {}", scene.lod_sets.len());
    let masked = scene
        .meshes
        .iter()
        .flat_map(|m| m.materials())
        .any(|m| matches!(m.alpha_mode, scanline_racer::render::AlphaMode::Mask { .. }));
    assert!(masked, "alpha-masked trees or fences");
    for cam in ["grid", "bridge", "overview"] {
        assert!(scene.find_camera(cam).is_some(), "camera {cam}");
    }
    assert!(scene.textures.iter().all(|t| t.width() <= 256 && t.height() <= 256));
}

#[test]
fn grid_frame_lod_saves_polygons_and_stays_close_to_the_reference() {
    let scene = load(&assets().join("grid.gltf")).unwrap();
    assert!(scene.lod_sets.len() >= 8 + 100, "cars and trees");
    let (w, h) = (480usize, 270usize);
    let camera = scene.find_camera("grid behind").expect("grid camera").camera;
    let bg = 0x0087ceeb;
    let reference = scanline_racer::measure::reference_frame(&camera, &scene.draw_list(), w, h, bg).unwrap();
    let mut results = vec![];
    for lod in [LodMode::Force(Level::Close), LodMode::Auto] {
        let mut frame = vec![0u32; w * h];
        let opts = RenderOptions {
            method: scanline_racer::render::Method::ZBuffer,
            lod,
            background: Some(bg),
            ..RenderOptions::default()
        };
        let s = Renderer::new().render(&mut frame, w, h, &camera, &scene.draw_list(), &opts).unwrap();
        let wrong = scanline_racer::measure::wrong_pixels(&frame, &reference);
        let psnr = scanline_racer::measure::psnr(&frame, &reference);
        eprintln!(
            "{lod:?}: polygons in {} drawn {} (close {} mid {} long {}, saved {}), wrong pixels {:.2}%, PSNR {:.2} dB",
            s.polygons_in,
            s.polygons_drawn,
            s.lod_close,
            s.lod_mid,
            s.lod_long,
            s.polygons_saved_by_lod,
            wrong * 100.0,
            psnr
        );
        results.push((s, wrong, psnr));
    }
    let (close, auto) = (&results[0], &results[1]);
    assert_eq!(close.0.lod_close, scene.lod_sets.len() as u64);
    assert!(
        auto.0.lod_close > 0 && auto.0.lod_mid > 0 && auto.0.lod_long > 0,
        "cars and trees near to far use every level"
    );
    assert!(auto.0.polygons_in * 10 < close.0.polygons_in * 9, "LOD saves at least 10% of the polygons");
    // LOD may cost a little accuracy, never much: at most one percentage point more wrong pixels.
    assert!(auto.1 <= close.1 + 0.01, "LOD wrong pixels {:.3} vs all-close {:.3}", auto.1, close.1);
}

#[test]
fn lod_sets_by_naming_convention_load_like_msft_lod() {
    // Rewrite car_4 without the extension: a parent node with children NAME_LOD0, NAME_LOD1, NAME_LOD2.
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("named-lods");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for e in std::fs::read_dir(assets().join("cars")).unwrap() {
        let p = e.unwrap().path();
        if p.file_name().unwrap().to_string_lossy().starts_with("car_4") {
            std::fs::copy(&p, dir.join(p.file_name().unwrap())).unwrap();
        }
    }
    let original = load(&dir.join("car_4.gltf")).unwrap();
    let text = std::fs::read_to_string(dir.join("car_4.gltf")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let nodes = v["nodes"].as_array().unwrap().clone();
    let primary = nodes.iter().position(|n| n.get("extensions").is_some()).unwrap();
    let ids: Vec<u64> = nodes[primary]["extensions"]["MSFT_lod"]["ids"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i.as_u64().unwrap())
        .collect();
    let mesh_of = |i: usize| nodes[i]["mesh"].clone();
    let named = serde_json::json!([
        {"name": "car", "children": [1, 2, 3]},
        {"name": "car_LOD0", "mesh": mesh_of(primary)},
        {"name": "car_LOD1", "mesh": mesh_of(ids[0] as usize)},
        {"name": "car_LOD2", "mesh": mesh_of(ids[1] as usize)},
    ]);
    v["nodes"] = named;
    v["scenes"] = serde_json::json!([{"nodes": [0]}]);
    v.as_object_mut().unwrap().remove("extensionsUsed");
    v.as_object_mut().unwrap().remove("cameras");
    std::fs::write(dir.join("named.gltf"), serde_json::to_vec(&v).unwrap()).unwrap();
    let named = load(&dir.join("named.gltf")).unwrap();
    assert_eq!(named.lod_sets.len(), 1);
    assert_eq!(named.instances.len(), 1, "LOD1 and LOD2 are not drawn on their own");
    assert!(named.instances[0].lod.is_some());
    let polys = |s: &scanline_racer::asset::LoadedScene| s.lod_sets[0].meshes.map(|m| s.meshes[m].polygons().len());
    assert_eq!(polys(&named), polys(&original));
    assert_eq!(named.lod_sets[0].switch_px, scanline_racer::asset::loader::DEFAULT_SWITCH_PX);
}

/// The assets built into the program are the committed folder's: the same scene, centre line and frames
/// (a replay of the demo race drawn both ways at three ticks, pixel for pixel).
#[test]
fn the_built_in_assets_draw_what_the_folder_draws() {
    use scanline_racer::input::replay::Replay;
    use scanline_racer::shell::race_scene::{DEFAULT_COURSE, RaceScene, View};
    let built_in = RaceScene::load_built_in(DEFAULT_COURSE).unwrap();
    let folder = RaceScene::load(&assets(), DEFAULT_COURSE).unwrap();
    assert_eq!(built_in.scene().polygon_count(), folder.scene().polygon_count());
    assert_eq!(built_in.scene().textures.len(), folder.scene().textures.len());
    assert_eq!(built_in.track.length(), folder.track.length());
    assert!(built_in.scene().files.is_empty(), "no file on disk is an input");
    let trace = assets().join("replays/demo-race.trace");
    let mut replay = Replay::open(&trace, folder.track.clone()).unwrap();
    let (w, h) = (160, 90);
    let mut renderer = Renderer::new();
    let mut drawn = 0;
    while replay.advance().unwrap() && drawn < 3 {
        if replay.world.tick.is_multiple_of(1500) {
            let mut a = vec![0u32; w * h];
            let mut b = vec![0u32; w * h];
            let o = RenderOptions::default();
            built_in.render(&mut renderer, &replay.world, View::ChaseNear, &o, (&mut a, w, h)).unwrap();
            folder.render(&mut renderer, &replay.world, View::ChaseNear, &o, (&mut b, w, h)).unwrap();
            assert!(a == b, "tick {}: the built-in assets draw another frame", replay.world.tick);
            drawn += 1;
        }
    }
    assert_eq!(drawn, 3);
}

/// A glTF of three copies of one quad (2 m wide, 3 m high, in the XY plane, facing +Z) side by side along
/// X, their meshes' extras `{"billboard": "y"}`, `{"billboard": "x"}` and none.
fn three_quads_gltf() -> serde_json::Value {
    use base64::Engine;
    let mut bin: Vec<u8> = vec![];
    for p in [[-1.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 3.0, 0.0], [-1.0, 3.0, 0.0]] {
        bin.extend(p.iter().flat_map(|c| c.to_le_bytes()));
    }
    bin.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    let prim = serde_json::json!([{"attributes": {"POSITION": 0}, "indices": 1}]);
    serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len(), "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 0.0, 0.0], "max": [1.0, 3.0, 0.0]},
            {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}
        ],
        "meshes": [
            {"primitives": prim, "extras": {"billboard": "y"}},
            {"primitives": prim, "extras": {"billboard": "x"}},
            {"primitives": prim}
        ],
        "nodes": [
            {"mesh": 0, "translation": [-20.0, 0.0, 0.0]},
            {"mesh": 1, "translation": [0.0, 0.0, 0.0]},
            {"mesh": 2, "translation": [20.0, 0.0, 0.0]}
        ],
        "scenes": [{"nodes": [0, 1, 2]}],
        "scene": 0
    })
}

/// A mesh whose extras say `"billboard": "y"` turns to face the eye: seen edge on it still shows its full
/// width, the same pixels from every side, where the same quad without it (or with another value) is a
/// sliver; and the mountain's trees are drawn so at a distance, never close by.
#[test]
fn a_mesh_marked_billboard_faces_the_eye_and_distant_trees_are_such_meshes() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("billboard");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("quads.gltf");
    std::fs::write(&path, serde_json::to_vec(&three_quads_gltf()).unwrap()).unwrap();
    let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let faces: Vec<bool> = scene.instances.iter().map(|i| scene.meshes[i.mesh].faces_eye()).collect();
    assert_eq!(faces, [true, false, false]);
    // Each quad alone, seen from eight sides at 12 m, level with its middle.
    let (w, h) = (160usize, 120usize);
    let mut r = Renderer::new();
    let mut covered = |k: usize, angle: f32| {
        let mut one = LoadedScene { instances: vec![scene.instances[k]], ..scene.clone() };
        one.instances[0].model = glam::Mat4::from_translation(Vec3::ZERO);
        let eye = Vec3::new(12.0 * libm::sinf(angle), 1.5, 12.0 * libm::cosf(angle));
        let camera = Camera::look_at(eye, Vec3::new(0.0, 1.5, 0.0), 0.8, 0.1, Some(100.0));
        let mut frame = vec![0u32; w * h];
        let o = RenderOptions { background: Some(0), ..RenderOptions::default() };
        r.render(&mut frame, w, h, &camera, &one.draw_list(), &o).unwrap();
        frame.iter().filter(|&&p| p != 0).count()
    };
    let facing: Vec<usize> = (0..8).map(|s| covered(0, s as f32 * std::f32::consts::FRAC_PI_4 + 0.1)).collect();
    let front = covered(2, 0.0);
    assert!(front > 500, "the quad seen square on covers {front} pixels");
    for &n in &facing {
        assert!(n.abs_diff(front) * 100 <= front, "a facing quad covers {facing:?}, seen square on {front}");
    }
    // Edge on, the quads that do not turn show (nearly) nothing.
    for k in [1, 2] {
        let edge = covered(k, std::f32::consts::FRAC_PI_2);
        assert!(edge * 20 < front, "quad {k} seen edge on covers {edge} pixels");
    }
    // export-frame writes the facing quad turned as the frame draws it: seen from +X, in the YZ plane.
    let camera = Camera::look_at(Vec3::new(-8.0, 1.5, 0.0), Vec3::new(-20.0, 1.5, 0.0), 0.8, 0.1, Some(100.0));
    let list = scene.draw_list();
    let chosen: Vec<Option<usize>> =
        scene.instances.iter().enumerate().map(|(k, i)| (k == 0).then_some(i.mesh)).collect();
    let (glb, _) = scanline_racer::asset::export::export_glb(&list, &chosen, &camera, (w, h)).unwrap();
    std::fs::write(dir.join("exported.glb"), glb).unwrap();
    let (lo, hi) = load(&dir.join("exported.glb")).unwrap().bounds.unwrap();
    assert!((hi.x - lo.x).abs() < 1e-4 && (hi.z - lo.z - 2.0).abs() < 1e-4, "exported quad spans {lo} to {hi}");
    // The mountain: every tree's middle and long models face the eye, its close model (crossed quads) not.
    let mountain = load(&assets().join("track/mountain/mountain.gltf")).unwrap();
    let turning = mountain
        .lod_sets
        .iter()
        .filter(|s| s.meshes[1..].iter().all(|&m| mountain.meshes[m].faces_eye()))
        .inspect(|s| assert!(!mountain.meshes[s.meshes[0]].faces_eye()))
        .count();
    assert!(turning >= 8000, "{turning} LOD sets with facing far models");
}
