//! `scanline-racer replay FILE`: a recorded race, in the window or headless to PNG frames.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use super::error::CliError;
use super::values;
use crate::input::replay::Replay;
use crate::render::{LodMode, Method, RenderOptions, Renderer};
use crate::shell::png::write_png;
use crate::shell::race::Race;
use crate::shell::race_scene::{FIELD, RaceScene, View};
use crate::shell::window::{WindowConfig, run};

/// Arguments of `replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The trace file (written by `play --record FILE`).
    pub trace: PathBuf,
    /// No window: simulate, check every checksum, and write frames if `--frames` is given.
    #[arg(long)]
    pub headless: bool,
    /// Folder for PNG frames (headless), named `frame_TICK.png`.
    #[arg(long)]
    pub frames: Option<PathBuf>,
    /// Write every Nth tick's frame (1 to 10^9).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u64).range(1..=1_000_000_000))]
    pub every: u64,
    /// Frame width (1 to 16384).
    #[arg(long, default_value_t = 640, value_parser = values::side(values::MAX_SIDE))]
    pub width: usize,
    /// Frame height (1 to 16384).
    #[arg(long, default_value_t = 360, value_parser = values::side(values::MAX_SIDE))]
    pub height: usize,
    /// Visibility method.
    #[arg(long, default_value = "zbuffer")]
    pub method: Method,
    /// Renderer worker threads (default: the cores available); frames are identical for every count.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Level of detail: auto, or close, mid or long for every car and tree.
    #[arg(long, default_value = "auto")]
    pub lod: LodMode,
    /// In the window: stop (freeze the frame) when the replay reaches this tick.
    #[arg(long)]
    pub stop_at: Option<u64>,
    /// In the window: draw no menus or HUD over the race.
    #[arg(long)]
    pub no_hud: bool,
}

/// What a headless replay did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReplaySummary {
    /// Ticks simulated.
    pub ticks: u64,
    /// Checksums that matched.
    pub verified: u64,
    /// Frames written.
    pub frames: u64,
}

/// Replays a trace without a window, checking checksums and writing frames; `progress` gets each tick.
pub fn replay_headless(args: &ReplayArgs, mut progress: impl FnMut(u64)) -> Result<ReplaySummary, CliError> {
    if let Some(d) = &args.frames {
        super::error::output_folder("--frames", d, "the PNG frames")?;
    }
    let dir = super::error::assets_dir()?;
    let scene = RaceScene::load(&dir)?;
    let mut replay = Replay::open(&args.trace, scene.track.clone(), FIELD)?;
    let options =
        RenderOptions { method: args.method, threads: args.threads, lod: args.lod, ..RenderOptions::default() };
    let mut renderer = Renderer::new();
    let mut frame = vec![0u32; args.width * args.height];
    let mut frames = 0;
    while replay.advance()? {
        let world = &replay.world;
        progress(world.tick);
        if let Some(d) = &args.frames
            && world.tick.is_multiple_of(args.every.max(1))
        {
            scene.render(&mut renderer, world, View::ChaseNear, &options, (&mut frame, args.width, args.height))?;
            write_png(&d.join(format!("frame_{:06}.png", world.tick)), &frame, args.width, args.height)?;
            frames += 1;
        }
    }
    Ok(ReplaySummary { ticks: replay.world.tick, verified: replay.source.verified, frames })
}

/// Runs `replay`.
pub fn replay_command(args: &ReplayArgs) -> Result<(), CliError> {
    if args.headless {
        let mut err = std::io::stderr();
        let terminal = std::io::IsTerminal::is_terminal(&err);
        let summary = replay_headless(args, |tick| {
            // A progress line on a terminal; nothing in a log.
            if terminal && tick.is_multiple_of(120) {
                let _ = write!(err, "\rreplaying: {:>6.1} s simulated", tick as f64 / 120.0);
                let _ = err.flush();
            }
        })?;
        eprintln!(
            "\rreplayed {} ticks ({:.1} s), {} checksums verified, {} frames written",
            summary.ticks,
            summary.ticks as f64 / 120.0,
            summary.verified,
            summary.frames
        );
        return Ok(());
    }
    let dir = super::error::assets_dir()?;
    let options =
        RenderOptions { method: args.method, threads: args.threads, lod: args.lod, ..RenderOptions::default() };
    let mut race =
        Race::replaying(RaceScene::load(&dir)?, options, &args.trace)?.stopping_at(args.stop_at, !args.no_hud);
    let window = WindowConfig {
        size: (args.width as u32, args.height as u32),
        fullscreen: false,
        scale: 1,
        exit_after_frames: None,
        screenshot: None,
    };
    run(window, &mut race)?;
    Ok(())
}
