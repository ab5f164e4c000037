//! Headless replays of the demo traces in `assets/replays/`, compared with stored expectations.
//!
//! - Exact determinism: every 600th tick (5 s) of every trace is rendered at 320x180 in `zbuffer` (the
//!   default) and in `bucket-near`, and an FNV-1a hash of each frame is compared with `tests/golden/replays.hashes`.
//!   The same frames are rendered with 1, 2 and 3 renderer threads and must hash the same.
//! - Perceptual goldens: a few frames per trace at 480x270 in the default method are compared with PNGs in
//!   `tests/golden/replay-*.png` by FLIP (the `nv-flip` crate). Threshold: mean FLIP at most 0.005 and at
//!   most 0.05% of pixels (65) with a FLIP error above 0.5. Measured on tick 1500 of the demo race
//!   (`cargo test --test integration replays::flip_threshold -- --nocapture`): the camera moved by 0.1 mm,
//!   a LOD bias of 0.5 and subdivided instead of exact perspective texturing score means of 0.0003-0.0034
//!   and at most 0.012% bad pixels, and pass; the nearest rival missing scores 0.0028 but 0.27% bad pixels,
//!   a band of the frame left unrendered 0.18 and 18%, and fail; so do bilinear filtering (0.026) and
//!   z-buffered instead of painter's visibility (0.011, 0.77%), changes big enough to regenerate on purpose.
//!
//! On failure the tests write the actual frame and the FLIP error map (magma colours) under
//! `target/golden-failures/` and print the command that regenerates the expectations on purpose:
//! `UPDATE_GOLDENS=1 cargo test --test integration replays::` (then look at the PNGs before committing them).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::common::*;
use scanline_racer::input::replay::Replay;
use scanline_racer::measure::flip;
use scanline_racer::render::{DepthKey, Filter, Method, RenderOptions, Renderer, TextureMode};
use scanline_racer::shell::race_scene::{DEFAULT_COURSE, RaceScene, View};

/// Ticks between hashed frames.
const HASH_EVERY: u64 = 600;
/// Size of hashed frames.
const HASH_SIZE: (usize, usize) = (320, 180);
/// Size of the perceptual goldens.
const GOLDEN_SIZE: (usize, usize) = (480, 270);
/// Mean FLIP a golden frame may reach.
const FLIP_MEAN_MAX: f32 = 0.005;
/// FLIP error above which a pixel counts as visibly wrong.
const FLIP_BAD: f32 = 0.5;
/// Share of visibly wrong pixels a golden frame may have (0.05%: 65 pixels at 480x270).
const FLIP_BAD_SHARE_MAX: f64 = 0.0005;

/// Whether a FLIP comparison is within the threshold.
fn within(f: &scanline_racer::measure::Flip) -> bool {
    f.mean <= FLIP_MEAN_MAX && f.share_above(FLIP_BAD) <= FLIP_BAD_SHARE_MAX
}

/// The ticks of each trace that have a PNG golden.
fn golden_ticks(trace: &str) -> &'static [u64] {
    match trace {
        "demo-race" => &[400, 1500, 6000, 11000],
        "scuffle" => &[900, 2400, 3600],
        "demo-city" => &[700, 2400, 6600, 9600],
        "demo-mountain" => &[1200, 3600, 9000, 10200],
        _ => &[1200],
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scene() -> RaceScene {
    RaceScene::load(&root().join("assets"), DEFAULT_COURSE).expect("race assets")
}

/// The scene of the course the trace at `path` was raced on (its header names it).
fn scene_of(path: &Path) -> RaceScene {
    let (header, _) = scanline_racer::input::trace::TraceReader::open(path).expect("trace header");
    RaceScene::load(&root().join("assets"), &header.course).expect("race assets")
}

/// Every committed demo trace, by name, in name order.
fn traces() -> Vec<(String, PathBuf)> {
    let mut v: Vec<(String, PathBuf)> = std::fs::read_dir(root().join("assets/replays"))
        .expect("assets/replays")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "trace"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), p))
        .collect();
    v.sort();
    v
}

fn fnv(px: &[u32]) -> u64 {
    px.iter()
        .flat_map(|p| p.to_le_bytes())
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3))
}

/// Replays `path` to its end, calling `at` with the world after every tick.
fn replay(scene: &RaceScene, path: &Path, mut at: impl FnMut(&scanline_racer::game::World)) -> u64 {
    let mut r = Replay::open(path, scene.track.clone()).unwrap_or_else(|e| panic!("{e}"));
    while r.advance().unwrap_or_else(|e| panic!("{e}")) {
        at(&r.world);
    }
    assert!(r.source.verified > 0, "{}: no checksum verified", path.display());
    r.world.tick
}

fn frame(
    scene: &RaceScene,
    r: &mut Renderer,
    w: &scanline_racer::game::World,
    o: &RenderOptions,
    size: (usize, usize),
) -> Vec<u32> {
    let mut px = vec![0u32; size.0 * size.1];
    scene.render(r, w, View::ChaseNear, o, (&mut px, size.0, size.1)).unwrap();
    px
}

fn updating() -> bool {
    let update = std::env::var_os("UPDATE_GOLDENS").is_some();
    assert!(!(update && std::env::var_os("CI").is_some()), "UPDATE_GOLDENS is for people, not CI");
    update
}

const REGENERATE: &str = "If the change is intended, regenerate with: UPDATE_GOLDENS=1 cargo test --test integration replays:: (then look at tests/golden/replay-*.png)";

#[test]
fn demo_traces_exist_and_one_is_a_full_field_race_of_a_minute_or_more() {
    let scene = scene();
    let t = traces();
    assert!(t.len() >= 3, "{t:?}");
    let longest = t.iter().map(|(_, p)| replay(&scene_of(p), p, |_| {})).max().unwrap();
    assert!(longest >= 60 * 120, "longest demo trace is {longest} ticks");
    let demo = Replay::open(&root().join("assets/replays/demo-race.trace"), scene.track.clone()).unwrap();
    assert_eq!(demo.source.header.cars, 8);
}

#[test]
fn replay_frames_hash_as_recorded_for_every_thread_count() {
    let update = updating();
    let hashes_path = root().join("tests/golden/replays.hashes");
    let mut got = BTreeMap::new();
    let methods = [Method::ZBuffer, Method::BucketNear];
    for (name, path) in traces() {
        let scene = scene_of(&path);
        let mut renderers: Vec<Renderer> = (0..3).map(|_| Renderer::new()).collect();
        replay(&scene, &path, |w| {
            if !w.tick.is_multiple_of(HASH_EVERY) {
                return;
            }
            for m in methods {
                let mut hashes = vec![];
                for (k, r) in renderers.iter_mut().enumerate() {
                    let o = RenderOptions { method: m, threads: k + 1, ..RenderOptions::default() };
                    hashes.push(fnv(&frame(&scene, r, w, &o, HASH_SIZE)));
                }
                assert!(
                    hashes.iter().all(|h| *h == hashes[0]),
                    "{name} tick {} {m}: threads differ {hashes:x?}",
                    w.tick
                );
                got.insert(format!("{name} {:>6} {m}", w.tick), hashes[0]);
            }
        });
    }
    let text: String = got.iter().map(|(k, h)| format!("{k} {h:016x}\n")).collect();
    if update {
        std::fs::write(&hashes_path, &text).unwrap();
        eprintln!("updated {}", hashes_path.display());
        return;
    }
    let stored = std::fs::read_to_string(&hashes_path).unwrap_or_default();
    if stored != text {
        let actual = root().join("target/golden-failures/replays.hashes");
        std::fs::create_dir_all(actual.parent().unwrap()).unwrap();
        std::fs::write(&actual, &text).unwrap();
        let first = stored.lines().zip(text.lines()).find(|(a, b)| a != b);
        panic!(
            "replay frame hashes differ from {}; first difference: {first:?} ({} stored, {} now)\n  actual: {}\n{REGENERATE}",
            hashes_path.display(),
            stored.lines().count(),
            text.lines().count(),
            actual.display()
        );
    }
}

#[test]
fn replay_frames_match_their_goldens_by_flip() {
    let update = updating();
    let (gw, gh) = GOLDEN_SIZE;
    let golden_dir = root().join("tests/golden");
    let fail_dir = root().join("target/golden-failures");
    let mut failures = vec![];
    let mut checked = 0;
    for (name, path) in traces() {
        let scene = scene_of(&path);
        let ticks = golden_ticks(&name);
        let mut r = Renderer::new();
        replay(&scene, &path, |w| {
            if !ticks.contains(&w.tick) {
                return;
            }
            let px = frame(&scene, &mut r, w, &RenderOptions::default(), GOLDEN_SIZE);
            let golden_path = golden_dir.join(format!("replay-{name}-{}.png", w.tick));
            if update {
                write_png(&golden_path, &px, gw, gh);
                eprintln!("updated {}", golden_path.display());
                return;
            }
            checked += 1;
            let Some((golden, w0, h0)) = read_png(&golden_path).filter(|g| (g.1, g.2) == GOLDEN_SIZE) else {
                failures.push(format!("{}: missing, unreadable or not {gw}x{gh}", golden_path.display()));
                return;
            };
            debug_assert_eq!((w0, h0), GOLDEN_SIZE);
            let f = flip(&golden, &px, gw, gh).unwrap();
            if !within(&f) {
                let actual = fail_dir.join(format!("replay-{name}-{}.actual.png", w.tick));
                let diff = fail_dir.join(format!("replay-{name}-{}.flip.png", w.tick));
                write_png(&actual, &px, gw, gh);
                write_png(&diff, &f.magma(gw, gh), gw, gh);
                failures.push(format!(
                    "{name} tick {}: FLIP mean {:.4} (max {FLIP_MEAN_MAX}), {:.3}% of pixels above {FLIP_BAD} (max {}%)\n  golden: {}\n  actual: {}\n  FLIP map: {}",
                    w.tick,
                    f.mean,
                    f.share_above(FLIP_BAD) * 100.0,
                    FLIP_BAD_SHARE_MAX * 100.0,
                    golden_path.display(),
                    actual.display(),
                    diff.display()
                ));
            }
        });
    }
    assert!(failures.is_empty(), "{}\n{REGENERATE}", failures.join("\n"));
    assert!(update || checked >= 5, "only {checked} golden frames were reached");
}

/// The FLIP threshold tells a change within noise from a broken frame, on a real replay frame.
#[test]
fn flip_threshold_separates_small_changes_from_broken_frames() {
    let scene = scene();
    let (gw, gh) = GOLDEN_SIZE;
    let mut world = None;
    replay(&scene, &root().join("assets/replays/demo-race.trace"), |w| {
        if w.tick == 1500 {
            world = Some(w.clone());
        }
    });
    let w = world.expect("tick 1500 reached");
    let mut r = Renderer::new();
    let mut render = |w: &scanline_racer::game::World, o: RenderOptions| frame(&scene, &mut r, w, &o, GOLDEN_SIZE);
    let base = render(&w, RenderOptions::default());
    let mut shifted = w.clone();
    shifted.cars[0].pos += glam::Vec2::new(0.0001, 0.0);
    let mut gone = w.clone();
    let me = gone.cars[0].pos;
    let nearest = (1..gone.cars.len())
        .min_by(|&a, &b| gone.cars[a].pos.distance(me).total_cmp(&gone.cars[b].pos.distance(me)))
        .unwrap();
    gone.cars[nearest].pos += glam::Vec2::new(0.0, 5000.0);
    let mut band = base.clone();
    band[gw * gh / 3..gw * gh / 2].fill(0x87ceeb);
    let cases: Vec<(&str, Vec<u32>, bool)> = vec![
        // Within noise: the camera moved by 0.1 mm; LOD bias nudged; subdivided instead of exact perspective.
        ("camera moved 0.1 mm", render(&shifted, RenderOptions::default()), true),
        ("LOD bias 0.5", render(&w, RenderOptions { lod_bias: 0.5, ..RenderOptions::default() }), true),
        (
            "subdivided texturing",
            render(&w, RenderOptions { texture_mode: TextureMode::Subdivided, ..RenderOptions::default() }),
            true,
        ),
        // Broken: the nearest rival missing; a band left unrendered.
        ("nearest rival missing", render(&gone, RenderOptions::default()), false),
        ("unrendered band", band, false),
        // Changes big enough to need new goldens on purpose.
        (
            "bilinear filtering",
            render(&w, RenderOptions { filter: Filter::Bilinear, ..RenderOptions::default() }),
            false,
        ),
        (
            "painter's order instead of the z-buffer",
            render(&w, RenderOptions { method: Method::BucketFar, key: DepthKey::Avg, ..RenderOptions::default() }),
            false,
        ),
    ];
    for (what, px, pass) in cases {
        let f = flip(&base, &px, gw, gh).unwrap();
        let share = f.share_above(FLIP_BAD);
        eprintln!("{what}: FLIP mean {:.4}, {:.3}% of pixels above {FLIP_BAD}", f.mean, share * 100.0);
        assert_eq!(within(&f), pass, "{what}: mean {} share {share}", f.mean);
    }
}

/// The ghost car is the player's fastest complete lap of a trace, and it is drawn see-through: every pixel
/// it changes is on the even squares of a checkerboard, and about as many odd ones show what is behind.
#[test]
fn the_ghost_is_the_fastest_lap_and_is_drawn_see_through() {
    use scanline_racer::input::ghost::best_lap_of_trace;
    let scene = scene();
    let demo = root().join("assets/replays/demo-race.trace");
    let lap = best_lap_of_trace(&demo, scene.track.clone()).unwrap().expect("the demo race has a lap");
    let mut best = None;
    let mut mid_lap = None;
    replay(&scene, &demo, |w| {
        best = w.race.standings[0].best_lap;
        if w.tick == 10800 {
            mid_lap = Some(w.clone());
        }
    });
    assert_eq!(Some(lap.ticks()), best, "ghost lap length is the race's best lap");
    let scuffle = root().join("assets/replays/scuffle.trace");
    assert_eq!(best_lap_of_trace(&scuffle, scene.track.clone()).unwrap(), None, "30 s: no complete lap");

    // The ghost where the same lap was 0.2 s later (alone on the straight), in the chase view.
    let w = mid_lap.unwrap();
    let into_lap = w.tick - w.race.standings[0].lap_start;
    let pose = lap.pose(into_lap + 24).unwrap();
    let (gw, gh) = GOLDEN_SIZE;
    let o = RenderOptions::default();
    for method in Method::ALL {
        let o = RenderOptions { method, ..o };
        let plain = frame(&scene, &mut Renderer::new(), &w, &o, GOLDEN_SIZE);
        let mut with = vec![0u32; gw * gh];
        scene
            .render_with_ghost(&mut Renderer::new(), &w, View::ChaseNear, &o, (&mut with, gw, gh), Some(pose))
            .unwrap();
        let changed: Vec<(usize, usize)> =
            (0..gw * gh).filter(|&i| plain[i] != with[i]).map(|i| (i % gw, i / gw)).collect();
        let odd = changed.iter().filter(|(x, y)| (x + y) % 2 == 1).count();
        assert!(changed.len() > 150, "{method}: the ghost is visible ({} pixels changed)", changed.len());
        // Painter's methods may differ on odd pixels only where the ghost's polygons reorder nothing: none.
        assert_eq!(odd, 0, "{method}: {odd} odd pixels changed");
    }
    // A ghost pose past the end of its lap is not drawn.
    assert_eq!(lap.pose(lap.ticks()), None);
    assert!(lap.pose(0).is_some());
}

/// The LOD choice over the demo race, frame by frame (every 5 s): polygons saved against drawing every
/// car and tree at its close level, and the image error that costs (wrong pixels against the close-level
/// frame). Bounds are the measured figures with a margin; the table prints with `--nocapture`.
#[test]
fn lod_choice_saves_polygons_at_a_bounded_image_cost_over_a_replay() {
    use scanline_racer::measure::wrong_pixels;
    use scanline_racer::render::{Level, LodMode};
    let scene = scene();
    let size = (480, 270);
    let (mut r_auto, mut r_close) = (Renderer::new(), Renderer::new());
    let (mut saved_sum, mut wrong_max, mut n) = (0.0f64, 0.0f64, 0);
    replay(&scene, &root().join("assets/replays/demo-race.trace"), |w| {
        if !w.tick.is_multiple_of(HASH_EVERY) {
            return;
        }
        let mut auto = vec![0u32; size.0 * size.1];
        let mut close = auto.clone();
        let o = RenderOptions { method: Method::ZBuffer, ..RenderOptions::default() };
        let sa = scene.render(&mut r_auto, w, View::ChaseNear, &o, (&mut auto, size.0, size.1)).unwrap();
        let oc = RenderOptions { lod: LodMode::Force(Level::Close), ..o };
        let sc = scene.render(&mut r_close, w, View::ChaseNear, &oc, (&mut close, size.0, size.1)).unwrap();
        let saved = sa.polygons_saved_by_lod as f64 / sc.polygons_in.max(1) as f64;
        let wrong = wrong_pixels(&close, &auto);
        eprintln!(
            "tick {:>6}: {} of {} polygons after LOD ({:.1}% saved), {:.3}% pixels differ from all-close",
            w.tick,
            sa.polygons_in,
            sc.polygons_in,
            saved * 100.0,
            wrong * 100.0
        );
        saved_sum += saved;
        wrong_max = wrong_max.max(wrong);
        n += 1;
    });
    let saved_mean = saved_sum / f64::from(n);
    eprintln!("mean saved {:.1}%, worst frame {:.3}% pixels differ", saved_mean * 100.0, wrong_max * 100.0);
    assert!(n >= 15);
    // Measured: 13-16% of the frame's polygons saved (all of them on cars and trees), at most 1.01% of
    // pixels differing from the all-close frame (0.82% when a distant tree was a quad fixed in the world:
    // the quad that faces the eye differs from the crossed quads in more pixels, by less, its FLIP against
    // the reference lower on every frame measured).
    assert!(saved_mean >= 0.12, "LOD saves {saved_mean}");
    assert!(wrong_max <= 0.0105, "worst frame {wrong_max}");
}
