//! `scanline-racer replay FILE`: a recorded race, in the window or headless to PNG frames.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use super::error::CliError;
use super::picture::PictureArgs;
use super::values;
use crate::audio::{CHANNELS, Mixer, wav};
use crate::input::replay::Replay;
use crate::render::{LodMode, Method, RenderOptions, Renderer};
use crate::shell::image_file::write_image;
use crate::shell::race::Race;
use crate::shell::race_scene::View;
use crate::shell::settings::{self, Settings, SettingsFile};
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
    /// Headless: write the race's soundtrack to this WAV file (48 kHz stereo, 16-bit PCM), the same bits on
    /// every run.
    #[arg(long, requires = "headless", value_parser = values::wav_path())]
    pub audio: Option<PathBuf>,
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
    /// Renderer worker threads, 0 to 256 (0, the default: the cores available); frames are identical for
    /// every count.
    #[arg(long, default_value_t = 0, value_parser = values::threads())]
    pub threads: usize,
    /// Level of detail: auto, or close, mid or long for every car and tree.
    #[arg(long, default_value = "auto")]
    pub lod: LodMode,
    /// Texture filter, mip levels and anti-aliasing.
    #[command(flatten)]
    pub picture: PictureArgs,
    /// In the window: stop (freeze the frame) when the replay reaches this tick.
    #[arg(long)]
    pub stop_at: Option<u64>,
    /// In the window: draw no menus or HUD over the race.
    #[arg(long)]
    pub no_hud: bool,
    /// In the window: draw frames as fast as the CPU allows instead of one per refresh of the display.
    #[arg(long)]
    pub uncapped: bool,
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

impl ReplayArgs {
    /// The renderer options these arguments ask for.
    #[must_use]
    pub fn options(&self) -> RenderOptions {
        self.picture.apply(RenderOptions {
            method: self.method,
            threads: self.threads,
            lod: self.lod,
            ..RenderOptions::default()
        })
    }
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
    /// Stereo sample frames of soundtrack written (0 without `--audio`).
    pub audio_frames: u64,
}

/// Replays a trace without a window, checking checksums and writing frames; `progress` gets each tick.
pub fn replay_headless(args: &ReplayArgs, mut progress: impl FnMut(u64)) -> Result<ReplaySummary, CliError> {
    if let Some(d) = &args.frames {
        super::error::output_folder("--frames", d, "the PNG frames")?;
    }
    if let Some(a) = &args.audio {
        crate::userfile::check_output(a).map_err(|source| CliError::Output { flag: "--audio", source })?;
    }
    let scene = args.assets.scene_for_trace(&args.trace)?;
    let mut inputs = crate::userfile::Inputs::new();
    inputs.add(&args.trace, "the trace");
    inputs.add_all(&scene.scene().files, super::error::ASSET_FILE);
    if let Some(a) = &args.audio {
        super::error::not_an_input("--audio", a, &inputs)?;
    }
    if let Some(d) = &args.frames {
        frames_not_inputs(d, &inputs)?;
    }
    let mut sound = args.audio.as_ref().map(|_| Soundtrack::new());
    let mut replay = Replay::open(&args.trace, scene.track.clone())?;
    let options = args.options();
    let mut renderer = Renderer::new();
    let mut frame = vec![0u32; args.width * args.height];
    let mut frames = 0;
    if let Some(s) = &mut sound {
        s.tick(&replay.world)?;
    }
    while replay.advance()? {
        let world = &replay.world;
        progress(world.tick);
        if let Some(s) = &mut sound {
            s.tick(world)?;
        }
        if let Some(d) = &args.frames
            && world.tick.is_multiple_of(args.every.max(1))
        {
            scene.render(&mut renderer, world, View::ChaseNear, &options, (&mut frame, args.width, args.height))?;
            write_image(&d.join(format!("frame_{:06}.png", world.tick)), &frame, args.width, args.height)?;
            frames += 1;
        }
    }
    let audio_frames = match (sound, &args.audio) {
        (Some(s), Some(path)) => s.write(path)?,
        _ => 0,
    };
    Ok(ReplaySummary { ticks: replay.world.tick, verified: replay.source.verified, frames, audio_frames })
}

/// Whether `name` is one a headless replay writes its frames under (`frame_TICK.png`, six digits or more).
fn is_frame_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|rest| rest.strip_suffix(".png"))
        .is_some_and(|tick| tick.len() >= 6 && tick.bytes().all(|b| b.is_ascii_digit()))
}

/// Refuses a frames folder in which a frame the replay may write is one of its `inputs` (the trace
/// renamed `frame_000060.png`, or a link to it under that name).
fn frames_not_inputs(dir: &std::path::Path, inputs: &crate::userfile::Inputs) -> Result<(), CliError> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Ok(()) };
    for entry in entries.flatten() {
        if is_frame_name(&entry.file_name().to_string_lossy()) {
            super::error::not_an_input("--frames", &entry.path(), inputs)?;
        }
    }
    Ok(())
}

/// A race's soundtrack as it is rendered: the mixer, and the WAV file's bytes so far (2 bytes a sample, so
/// an hour of racing holds 691 MB; the format's 4 GiB limit is checked as it grows).
struct Soundtrack {
    mixer: Mixer,
    block: Vec<f32>,
    bytes: Vec<u8>,
}

impl Soundtrack {
    fn new() -> Self {
        Self { mixer: Mixer::new(), block: vec![], bytes: vec![0; wav::HEADER_BYTES] }
    }

    /// The sound of the tick that led to `world` (the WAV's samples `400 t .. 400 (t + 1)` follow tick `t`).
    fn tick(&mut self, world: &crate::game::World) -> Result<(), CliError> {
        self.mixer.advance(world);
        self.mixer.render(&mut self.block);
        self.flush()
    }

    fn flush(&mut self) -> Result<(), CliError> {
        wav::append(&self.block, &mut self.bytes);
        self.block.clear();
        if self.bytes.len() > wav::MAX_BYTES {
            return Err(CliError::AudioTooLong { hours: wav::MAX_BYTES as f64 / wav::bytes_per_second() / 3600.0 });
        }
        Ok(())
    }

    /// Ends the sound cleanly and writes the file; returns the frames written.
    fn write(mut self, path: &std::path::Path) -> Result<u64, CliError> {
        self.mixer.finish(&mut self.block);
        self.flush()?;
        let frames = (self.bytes.len() - wav::HEADER_BYTES) / (2 * CHANNELS);
        let head = wav::header(frames)
            .ok_or(CliError::AudioTooLong { hours: wav::MAX_BYTES as f64 / wav::bytes_per_second() / 3600.0 })?;
        self.bytes[..wav::HEADER_BYTES].copy_from_slice(&head);
        crate::userfile::replace_atomically(path, &self.bytes).map_err(CliError::Write)?;
        Ok(frames as u64)
    }
}

/// Runs `replay`.
pub fn replay_command(args: &ReplayArgs) -> Result<(), CliError> {
    if args.headless {
        args.picture.fixed_for("replay --headless")?;
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
            "\rreplayed {} ticks ({:.1} s), {} checksums verified, {} frames written{}",
            summary.ticks,
            summary.ticks as f64 / 120.0,
            summary.verified,
            summary.frames,
            match &args.audio {
                Some(p) => format!(", {:.1} s of sound to {}", summary.audio_frames as f64 / 48_000.0, p.display()),
                None => String::new(),
            }
        );
        return Ok(());
    }
    let options = args.options();
    // The settings file's sound levels, mute and keys apply to a replay too (the window keeps its scale).
    let (file, settings, note) = match settings::default_path().as_deref().map(SettingsFile::load) {
        Some((file, settings, note)) => (Some(file), settings, note),
        None => (None, Settings::default(), None),
    };
    if let Some(n) = &note {
        eprintln!("warning: {n}");
    }
    // A windowed replay follows the frame time only when asked (`--quality auto`); the HUD says so.
    let mut race = Race::replaying(args.assets.scene_for_trace(&args.trace)?, options, &args.trace)?
        .with_auto_quality(args.picture.auto() == Some(true))
        .stopping_at(args.stop_at, !args.no_hud)
        .with_settings(settings, file, Some(1), note)
        .with_sound();
    let window = WindowConfig {
        size: (args.width as u32, args.height as u32),
        fullscreen: false,
        scale: 1,
        exit_after_frames: None,
        screenshot: None,
        paced: !args.uncapped,
        fps: None,
    };
    let signals = crate::shell::stop::StopSignals::catch();
    super::error::stopped(run(window, &mut race, signals.as_ref())?)
}
