//! `assetgen`: writes the shipped assets (`assets/cars`, `assets/track`, `assets/grid.gltf`,
//! `assets/replays`) from code.
//!
//! Deterministic: no clock, no OS randomness, no hash-map iteration; running it twice gives identical
//! bytes, and `tests/integration/assets.rs` checks that the committed assets equal what it makes.
//! Usage: `cargo run --release --bin assetgen [-- OUT_DIR]` (default `assets`).

mod cars;
mod gltf_out;
mod grid;
mod paint;
mod replays;
mod track;

use std::path::PathBuf;
use std::process::ExitCode;

fn run(out: &std::path::Path) -> std::io::Result<()> {
    let cars_dir = out.join("cars");
    std::fs::create_dir_all(&cars_dir)?;
    let cars = cars::generate(&cars_dir)?;
    let mut circuit = None;
    for layout in track::COURSES {
        let dir = out.join("track").join(layout.name);
        std::fs::create_dir_all(&dir)?;
        let info = track::generate(&dir, layout)?;
        circuit.get_or_insert(info);
    }
    grid::generate(out, &cars, &circuit.unwrap_or_default())?;
    replays::generate(&out.join("replays"), &out.join("track"))
}

fn main() -> ExitCode {
    let out = std::env::args_os().nth(1).map_or_else(|| PathBuf::from("assets"), PathBuf::from);
    match run(&out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("assetgen: error: {e}");
            ExitCode::from(1)
        }
    }
}
