//! No command writes over a file it reads, whatever path names it (a link, a hard link, `..`); an output's
//! extension chooses its format or is a usage error naming those accepted; a write that cannot happen says
//! what stands in its way. Every refusal is one line, before anything is drawn, and leaves the files as
//! they were.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::*;

fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("outputs").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The game run from the repository with no display and no settings file of the developer's.
fn run(args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    c.args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("SCANLINE_RACER_RECORDS", Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("SCANLINE_RACER_SETTINGS", folder("settings").join("none.json"));
    run_bounded(&mut c, 60, &args.join(" "))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The one line refusing `flag`'s output `path` because it is `what`.
fn is_input(flag: &str, path: &Path, what: &str) -> String {
    format!(
        "scanline-racer: error: cannot write {flag} {}: it is {what}, which this command reads (name another file \
         for the output)",
        path.display()
    )
}

fn assert_line(o: &Output, want: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!((o.status.code(), err.trim_end()), (Some(1), want), "{err}");
}

#[test]
fn an_output_that_is_the_scene_or_a_file_it_names_is_refused_by_any_path() {
    let d = folder("render");
    let duck = samples().join("Duck");
    for f in ["Duck.gltf", "Duck0.bin", "DuckCM.png"] {
        std::fs::copy(duck.join(f), d.join(f)).unwrap();
    }
    let scene = d.join("Duck.gltf");
    let before = files_under(&d);
    // The texture the scene names, as itself and through `..`.
    let texture = d.join("DuckCM.png");
    assert_line(
        &run(&["render", s(&scene), "--out", s(&texture)]),
        &is_input("--out", &texture, "a file the glTF scene names"),
    );
    let dotted = d.join("sub/../DuckCM.png");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    assert_line(
        &run(&["render", s(&scene), "--out", s(&dotted)]),
        &is_input("--out", &dotted, "a file the glTF scene names"),
    );
    // The scene through a symbolic link and a hard link with an image's name.
    let link = d.join("link.png");
    std::os::unix::fs::symlink("Duck.gltf", &link).unwrap();
    assert_line(&run(&["render", s(&scene), "--out", s(&link)]), &is_input("--out", &link, "the glTF scene"));
    let hard = d.join("hard.jpg");
    std::fs::hard_link(&scene, &hard).unwrap();
    assert_line(&run(&["render", s(&scene), "--out", s(&hard)]), &is_input("--out", &hard, "the glTF scene"));
    for (name, bytes) in &before {
        assert_eq!(&std::fs::read(d.join(name)).unwrap(), bytes, "{} is as it was", name.display());
    }
    // A new name is written, in the format its extension names.
    let out = d.join("duck.jpeg");
    let o = run(&["render", s(&scene), "--out", s(&out), "--width", "64", "--height", "48"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(image::guess_format(&bytes).unwrap(), image::ImageFormat::Jpeg);
}

#[test]
fn a_trace_settings_file_or_asset_is_never_an_output() {
    let d = folder("traces");
    let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/replays/demo-race.trace");
    let bytes = std::fs::read(&demo).unwrap();
    // Traces saved under the names an output would take.
    let wav = d.join("race.wav");
    let glb = d.join("race.glb");
    let frames = d.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    let frame = frames.join("frame_000060.png");
    for p in [&wav, &glb, &frame] {
        std::fs::write(p, &bytes).unwrap();
    }
    assert_line(&run(&["replay", s(&wav), "--headless", "--audio", s(&wav)]), &is_input("--audio", &wav, "the trace"));
    assert_line(
        &run(&["export-frame", s(&glb), "--tick", "60", "--out", s(&glb)]),
        &is_input("--out", &glb, "the trace"),
    );
    assert_line(
        &run(&["replay", s(&frame), "--headless", "--frames", s(&frames)]),
        &is_input("--frames", &frame, "the trace"),
    );
    let csv = d.join("bench.csv");
    std::fs::write(&csv, &bytes).unwrap();
    let o = run(&["bench", "--quick", "--trace", s(&csv), "--out", s(&d)]);
    assert_line(&o, &is_input("--out", &csv, "the trace"));
    // The game's assets (a folder of them, as a user editing them names it), and play's settings file,
    // are inputs too.
    let assets = d.join("assets");
    copy_assets(&assets);
    let texture = assets.join("track/circuit/asphalt.png");
    let before = std::fs::read(&texture).unwrap();
    let o = run(&["play", "--assets", s(&assets), "--screenshot", s(&texture)]);
    assert_line(&o, &is_input("--screenshot", &texture, "a file of the game's assets"));
    assert_eq!(std::fs::read(&texture).unwrap(), before);
    let settings = d.join("settings.png");
    std::fs::write(&settings, b"{}").unwrap();
    let o = run(&["play", "--settings", s(&settings), "--screenshot", s(&settings)]);
    assert_line(&o, &is_input("--screenshot", &settings, "the settings file"));
    let o = run(&["play", "--settings", s(&settings), "--record", s(&settings)]);
    assert_line(&o, &is_input("--record", &settings, "the settings file"));
    let o = run(&["play", "--record", s(&d.join("same.png")), "--screenshot", s(&d.join("./same.png"))]);
    assert_line(
        &o,
        &format!(
            "scanline-racer: error: cannot write --screenshot {}: --record names the same file",
            d.join("./same.png").display()
        ),
    );
    for p in [&wav, &glb, &frame, &csv] {
        assert_eq!(std::fs::read(p).unwrap(), bytes, "{} is as it was", p.display());
    }
    assert_eq!(std::fs::read(&settings).unwrap(), b"{}");
}

#[test]
fn an_extension_no_writer_knows_is_a_usage_error_naming_those_accepted() {
    let scene = "tests/scenes/courtyard.gltf";
    let trace = "assets/replays/demo-race.trace";
    let images = "(accepted: .png, .jpg or .jpeg)";
    for (args, want) in [
        (vec!["render", scene, "--out", "x.gif"], format!("unknown extension '.gif' {images}")),
        (vec!["render", scene, "--out", "frame"], format!("no extension to choose the format by {images}")),
        (vec!["play", "--screenshot", "s.bmp"], format!("unknown extension '.bmp' {images}")),
        (
            vec!["export-frame", trace, "--tick", "1", "--out", "f.gltf"],
            "unknown extension '.gltf' (accepted: .glb)".into(),
        ),
        (vec!["replay", trace, "--headless", "--audio", "a.mp3"], "unknown extension '.mp3' (accepted: .wav)".into()),
    ] {
        let o = run(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        let first = err.lines().next().unwrap_or_default();
        assert!(first.starts_with("error: invalid value") && first.ends_with(&want), "{args:?}: {err}");
    }
}

#[test]
fn a_write_that_cannot_happen_names_the_folder_in_its_way() {
    let d = folder("folders");
    let file = d.join("a-file");
    std::fs::write(&file, b"mine").unwrap();
    let scene = "tests/scenes/courtyard.gltf";
    let missing = d.join("no/dir/s.png");
    let no_folder = format!("no such folder {}", d.join("no/dir").display());
    let o = run(&["play", "--screenshot", s(&missing)]);
    assert_line(&o, &format!("scanline-racer: error: cannot write --screenshot {}: {no_folder}", missing.display()));
    let o = run(&["render", scene, "--out", s(&missing)]);
    assert_line(&o, &format!("scanline-racer: error: cannot write --out {}: {no_folder}", missing.display()));
    let under = file.join("s.png");
    let o = run(&["render", scene, "--out", s(&under)]);
    let not_folder = format!("{} is a file, not a folder", file.display());
    assert_line(&o, &format!("scanline-racer: error: cannot write --out {}: {not_folder}", under.display()));
    let trace = d.join("no/dir/race.trace");
    let o = run(&["play", "--record", s(&trace)]);
    assert_line(&o, &format!("scanline-racer: error: cannot record to {}: {no_folder}", trace.display()));
    // A folder that takes no new files (a virtual file system).
    let o = run(&["render", scene, "--out", "/proc/frame.png"]);
    assert_line(
        &o,
        "scanline-racer: error: cannot write --out /proc/frame.png: the folder /proc takes no new files (entity not \
         found)",
    );
    assert_eq!(std::fs::read(&file).unwrap(), b"mine");
}
