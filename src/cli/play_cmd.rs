//! `scanline-racer play`: the window.

use std::path::{Path, PathBuf};

use clap::Args;

use super::error::{CliError, say, stopped};
use super::picture::PictureArgs;
use super::values;
use crate::asset::{LoadedScene, load, loader::load_from_slice};
use crate::input::ghost::GhostSearch;
use crate::input::recording::Kept;
use crate::render::{Method, RenderOptions};
use crate::shell::race::Race;
use crate::shell::race_scene::RaceScene;
use crate::shell::settings::{self, Settings, SettingsFile};
use crate::shell::stop::StopSignals;
use crate::shell::viewer::Viewer;
use crate::shell::window::{Ended, WindowConfig, run};
use crate::userfile::Inputs;

/// The scene shown when no `--scene` is given: the hand-made test courtyard (self-contained, data URIs only).
const DEMO_SCENE: &[u8] = include_bytes!("../../tests/scenes/courtyard.gltf");

/// Arguments of `play`.
#[derive(Debug, Args)]
pub struct PlayArgs {
    /// The course to race: circuit, city, ... (`scanline-racer courses` lists them). Default: the settings
    /// file's (the last chosen in the menu), else circuit.
    #[arg(long, value_name = "NAME", value_parser = values::course_name)]
    pub course: Option<String>,
    /// Window width in pixels (1 to 16384).
    #[arg(long, default_value_t = 1280, value_parser = values::window_side())]
    pub width: u32,
    /// Window height in pixels (1 to 16384).
    #[arg(long, default_value_t = 720, value_parser = values::window_side())]
    pub height: u32,
    /// Start in fullscreen (F11 toggles).
    #[arg(long)]
    pub fullscreen: bool,
    /// Window pixels per rendered pixel, 1 to 8 (1 = native; 2-4 for the retro look; '-' and '=' change
    /// it). Default: the settings file's, else 1.
    #[arg(long, value_parser = values::scale())]
    pub scale: Option<u32>,
    /// The settings file (keys, gamepad, scale, sound, picture), read at start and written when Settings
    /// change. Default: $SCANLINE_RACER_SETTINGS, else $XDG_CONFIG_HOME/scanline-racer/settings.json.
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// The records file (best laps and races; the time trial's ghosts are kept beside it). Default:
    /// $SCANLINE_RACER_RECORDS, else $XDG_DATA_HOME/scanline-racer/records.json, else
    /// ~/.local/share/scanline-racer/records.json.
    #[arg(long, value_name = "FILE")]
    pub records: Option<PathBuf>,
    /// Visibility method (keys 1-5 switch: zbuffer, sort, bucket-far, bucket-near, view-lists).
    #[arg(long, default_value_t = RenderOptions::default().method)]
    pub method: Method,
    /// Texture filter, mip levels and anti-aliasing.
    #[command(flatten)]
    pub picture: PictureArgs,
    /// Renderer worker threads, 0 to 256 (0, the default: the cores available).
    #[arg(long, default_value_t = 0, value_parser = values::threads())]
    pub threads: usize,
    /// Fly a camera around this glTF scene instead of racing.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Fly a camera around the built-in demo scene instead of racing.
    #[arg(long, conflicts_with = "scene")]
    pub demo: bool,
    /// Record the race to this trace file (replay it with `scanline-racer replay FILE`).
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Race against the fastest lap in this trace, as a see-through ghost car (the trace is replayed in the
    /// background while the race runs; each faster lap found takes over at the line).
    #[arg(long)]
    pub ghost: Option<PathBuf>,
    /// Let the AI drive your car (attract mode; with --record it makes a demo trace).
    #[arg(long)]
    pub autopilot: bool,
    /// Start racing at once instead of showing the main menu.
    #[arg(long)]
    pub no_menu: bool,
    /// Laps in the race (1 to 99). Default: the settings file's, else 3.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=values::MAX_LAPS))]
    pub laps: Option<u32>,
    /// Your car, 1 to 8 (each handles differently: `scanline-racer cars` lists them). Default: the
    /// settings file's (the last chosen in the menu), else 1.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=crate::game::garage::CARS as i64))]
    pub car: Option<u32>,
    /// The mode: race (against the AI) or time-trial (alone, against the ghost of your best lap). Default:
    /// the settings file's, else race.
    #[arg(long, value_parser = values::mode)]
    pub mode: Option<crate::game::Mode>,
    /// How fast the AI drives: easy, normal or hard. Default: the settings file's, else normal.
    #[arg(long, value_parser = values::difficulty)]
    pub difficulty: Option<crate::game::Difficulty>,
    /// Quit after this many frames (for tests and screenshots).
    #[arg(long)]
    pub exit_after_frames: Option<u64>,
    /// Draw frames as fast as the CPU allows instead of one per refresh of the display (for measuring
    /// frame times; F3 says which is in use).
    #[arg(long)]
    pub uncapped: bool,
    /// Pace frames to this many a second (20 to 1000) instead of the display's refresh rate; `auto`
    /// quality budgets against it.
    #[arg(long, value_name = "HZ", conflicts_with = "uncapped", value_parser = values::parse_fps)]
    pub fps: Option<f64>,
    /// Write the last frame to this image when quitting, PNG or JPEG by its extension (.png, .jpg, .jpeg).
    #[arg(long, value_parser = values::image_path())]
    pub screenshot: Option<PathBuf>,
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

impl Default for PlayArgs {
    fn default() -> Self {
        Self {
            course: None,
            width: 1280,
            height: 720,
            fullscreen: false,
            scale: None,
            settings: None,
            method: RenderOptions::default().method,
            picture: PictureArgs::default(),
            threads: 0,
            scene: None,
            demo: false,
            autopilot: false,
            record: None,
            ghost: None,
            no_menu: false,
            laps: None,
            car: None,
            records: None,
            mode: None,
            difficulty: None,
            exit_after_frames: None,
            uncapped: false,
            fps: None,
            screenshot: None,
            assets: super::error::AssetsArg::default(),
        }
    }
}

/// The race's drawing options: `options` with the settings file's picture, unless the command line's
/// `picture` says otherwise for this run.
fn race_options(options: RenderOptions, settings: &Settings, picture: &PictureArgs) -> RenderOptions {
    picture.apply(RenderOptions {
        antialias: settings.antialias,
        filter: settings.filter,
        mip: settings.mip,
        lod_fade: settings.lod_fade,
        lod_bias: settings.lod_bias,
        mip_bias: settings.mip_bias,
        ..options
    })
}

/// Refuses a screenshot or a recording that would be written over one of `inputs` or over each other,
/// and a screenshot over the `ghost` trace. A recording may replace the ghost's trace: the race is
/// written beside it and renamed over it only at the end, while the search reads the file it opened.
fn outputs_not_inputs(args: &PlayArgs, inputs: &Inputs, ghost: Option<&Path>) -> Result<(), CliError> {
    if let Some(record) = &args.record {
        super::error::not_an_input("--record", record, inputs)?;
    }
    if let Some(shot) = &args.screenshot {
        let mut inputs = inputs.clone();
        if let Some(g) = ghost {
            inputs.add(g, "the ghost's trace");
        }
        super::error::not_an_input("--screenshot", shot, &inputs)?;
        if let Some(record) = &args.record {
            crate::userfile::check_distinct(shot, record, "--record")
                .map_err(|source| CliError::Output { flag: "--screenshot", source })?;
        }
    }
    Ok(())
}

/// Runs `play`.
pub fn play_command(args: PlayArgs) -> Result<(), CliError> {
    let options = RenderOptions { method: args.method, threads: args.threads, ..RenderOptions::default() };
    let window = WindowConfig {
        size: (args.width, args.height),
        fullscreen: args.fullscreen,
        scale: args.scale.unwrap_or(1),
        exit_after_frames: args.exit_after_frames,
        screenshot: args.screenshot.clone(),
        paced: !args.uncapped,
        fps: args.fps,
    };
    if let Some(shot) = &args.screenshot {
        crate::userfile::check_output(shot).map_err(|source| CliError::Output { flag: "--screenshot", source })?;
    }
    let aspect = args.width as f32 / args.height as f32;
    let scene: Option<LoadedScene> = match &args.scene {
        Some(path) => Some(load(path)?),
        None if args.demo => Some(load_from_slice(DEMO_SCENE, std::path::Path::new("."), "built-in demo scene")?),
        None => None,
    };
    match scene {
        Some(scene) => {
            let mut inputs = Inputs::new();
            inputs.add_all(&scene.files, "a file of the scene");
            outputs_not_inputs(&args, &inputs, None)?;
            let signals = StopSignals::catch();
            let viewer = &mut Viewer::new(scene, args.picture.apply(options), aspect);
            stopped(run(window, viewer, signals.as_ref())?)?;
        }
        None => race(&args, options, window)?,
    }
    Ok(())
}

/// The race `play` starts with: the command line's choices, else the settings file's (the race last
/// chosen in the menu); a course the settings name that `assets` do not hold gives way to the first
/// course, said in one line.
fn chosen_race(
    args: &PlayArgs,
    settings: &Settings,
    assets: &crate::shell::race_scene::Assets,
) -> (String, crate::game::RaceSetup) {
    let course = match &args.course {
        Some(c) => c.clone(),
        None if assets.course_names().contains(&settings.course) => settings.course.clone(),
        None => match assets.course_names().into_iter().next() {
            Some(first) => {
                say(&format!("note: the settings' course {:?} is not in these assets: {first} raced", settings.course));
                first
            }
            // None at all: loading says so, naming the folder.
            None => settings.course.clone(),
        },
    };
    let setup = crate::game::RaceSetup {
        mode: args.mode.unwrap_or(settings.mode),
        laps: args.laps.unwrap_or(settings.laps),
        car: args.car.unwrap_or(settings.car).saturating_sub(1) as usize,
        difficulty: args.difficulty.unwrap_or(settings.difficulty),
        ..crate::game::RaceSetup::default()
    };
    (course, setup)
}

/// Runs the race of `play`: the assets, the settings, the ghost and the recording, then the window; what
/// was recorded is kept however the window closed.
fn race(args: &PlayArgs, options: RenderOptions, window: WindowConfig) -> Result<(), CliError> {
    let path = args.settings.clone().or_else(settings::default_path);
    let (file, settings, note) = match path.as_deref().map(SettingsFile::load) {
        Some((file, settings, note)) => (Some(file), settings, note),
        None => (None, Settings::default(), None),
    };
    if let Some(n) = &note {
        say(&format!("warning: {n}"));
    }
    let assets = args.assets.find();
    let (course, setup) = chosen_race(args, &settings, &assets);
    let scene = RaceScene::open(&assets, &course)?;
    let mut inputs = Inputs::new();
    inputs.add_all(&scene.scene().files, super::error::ASSET_FILE);
    if let Some(p) = &path {
        inputs.add(p, "the settings file");
    }
    let records = args.records.clone().or_else(crate::shell::records::default_path);
    if let Some(p) = &records {
        inputs.add(p, "the records file");
    }
    outputs_not_inputs(args, &inputs, args.ghost.as_deref())?;
    // The trace is checked now; its laps are searched on a background thread while the race runs.
    if let Some(p) = args.ghost.as_deref() {
        crate::input::replay::TraceSource::open(p)?.check_course(&scene.course)?;
    }
    let ghost = args.ghost.as_deref().map(|p| GhostSearch::start(p, scene.track.clone())).transpose()?;
    let auto = args.picture.auto().unwrap_or(settings.auto_quality);
    let mut race = Race::new(scene, race_options(options, &settings, &args.picture), setup, !args.no_menu)
        .with_auto_quality(auto)
        .autopilot(args.autopilot)
        .with_settings(settings, file, args.scale, note)
        .with_courses(assets)
        .with_sound();
    if let Some(p) = &records {
        let (file, problem) = crate::shell::records::RecordsFile::load(p);
        if let Some(e) = problem {
            say(&format!("warning: {e}"));
        }
        race = race.with_records(file);
    }
    if let Some(search) = ghost {
        race = race.with_ghost_search(search);
    }
    race = race.reading(inputs);
    if let Some(path) = &args.record {
        if let Some(left) = crate::input::recording::left_behind(path) {
            say(&format!("note: {left}"));
        }
        race = race.record_to(path)?;
    }
    // Caught from before the window opens until the recording is kept (dropped at the end).
    let signals = StopSignals::catch();
    let ran = run(window, &mut race, signals.as_ref());
    // However the window closed (a stop signal too), what was raced replaces the target (or stays
    // in its temporary file, named in the one-line error, when the rename fails).
    match (race.finish_recording(), ran) {
        (Ok(kept), Ok(Ended::Signal(signal))) => Err(CliError::Stopped { signal, kept }),
        (Ok(kept), ran) => {
            // A race kept is always said; nothing recorded only when the window ran (not before
            // the one-line error that it could not open).
            if let Some(kept) = kept.filter(|k| ran.is_ok() || matches!(k, Kept::Race { .. })) {
                say(&kept.to_string());
            }
            ran?;
            Ok(())
        }
        (Err(e), Ok(_)) => Err(e.into()),
        (Err(e), Err(ran)) => {
            say(&format!("scanline-racer: error: {e}"));
            Err(ran.into())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{Antialias, Filter, MipMode};

    #[test]
    fn the_race_takes_the_settings_file_s_picture_and_a_flag_wins_for_the_run() {
        let settings = Settings {
            antialias: Antialias::Supersample2x2,
            filter: Filter::Bilinear,
            mip: MipMode::Span,
            ..Settings::default()
        };
        let base = RenderOptions { method: Method::BucketNear, threads: 3, ..RenderOptions::default() };
        let got = race_options(base, &settings, &PictureArgs::default());
        assert_eq!((got.antialias, got.filter, got.mip), (Antialias::Supersample2x2, Filter::Bilinear, MipMode::Span));
        assert_eq!((got.method, got.threads), (Method::BucketNear, 3), "the rest is the command line's");
        let flags = PictureArgs { aa: Some(Antialias::Off), mip: Some(MipMode::Pixel), ..PictureArgs::default() };
        let got = race_options(base, &settings, &flags);
        assert_eq!((got.antialias, got.filter, got.mip), (Antialias::Off, Filter::Bilinear, MipMode::Pixel));
    }
}
