//! Why a command failed: each module's typed error, wrapped for the user's one line, and the checks on the
//! command line's paths that fail before any long work.

use thiserror::Error;

/// Why a command failed.
#[derive(Debug, Error)]
pub enum CliError {
    /// The scene could not be loaded.
    #[error(transparent)]
    Asset(#[from] crate::asset::AssetError),
    /// The race's circuit, cars or centre line could not be loaded.
    #[error(transparent)]
    RaceScene(#[from] crate::shell::race_scene::RaceSceneError),
    /// The renderer refused the frame.
    #[error("render: {0}")]
    Render(#[from] crate::render::RenderError),
    /// `--camera` names no camera in the scene.
    #[error("{file}: no camera '{wanted}' (the scene has {count} camera node(s){names})")]
    NoSuchCamera {
        /// The scene file.
        file: String,
        /// What was asked for.
        wanted: String,
        /// How many cameras exist.
        count: usize,
        /// Their names, for the message.
        names: String,
    },
    /// An output file could not be written.
    #[error("cannot write {0}")]
    Write(#[source] crate::userfile::UserFileError),
    /// An output folder's path names a file.
    #[error("{flag} {path}: is a file, not a folder; name a folder (new or existing) for {what}")]
    NotAFolder {
        /// The flag that named it.
        flag: &'static str,
        /// The path.
        path: String,
        /// What the folder is for.
        what: &'static str,
    },
    /// An output folder cannot be created or written into.
    #[error("{flag} {path}: cannot write into this folder: {problem}")]
    FolderNotWritable {
        /// The flag that named it.
        flag: &'static str,
        /// The path.
        path: String,
        /// What stands in the way.
        #[source]
        problem: crate::userfile::WriteProblem,
    },
    /// `bench --course NAME` names a course with no demo race in the assets folder.
    #[error("bench: no demo race of the course {course} in {} (a replays/demo-*.trace whose header names it)", folder.display())]
    NoDemoTrace {
        /// The course.
        course: String,
        /// The folder looked in.
        folder: std::path::PathBuf,
    },
    /// `courses` found none.
    #[error("no courses in {place} (a course is a folder NAME holding NAME.gltf and centerline.json)")]
    NoCourses {
        /// Where they were looked for.
        place: String,
    },
    /// `bench` has no trace to measure: none named, and the assets are the built-in ones (no folder with
    /// the demo traces).
    #[error("bench: name a trace to measure with --trace FILE (the built-in assets hold no demo trace)")]
    NoTrace,
    /// A frame could not be written out as GLB.
    #[error("export-frame: {0}")]
    Export(#[from] crate::asset::export::ExportError),
    /// A bench chart could not be drawn.
    #[error("bench chart '{name}': {source}")]
    Chart {
        /// The chart's file name stem.
        name: String,
        /// Why.
        source: crate::bench::chart::ChartError,
    },
    /// The window could not be opened or failed.
    #[error(transparent)]
    Shell(#[from] crate::shell::window::ShellError),
    /// `export-frame --tick` asks for a tick after the trace's end.
    #[error("{trace}: the trace ends at tick {ends_at}, before tick {wanted}")]
    TraceTooShort {
        /// The trace.
        trace: std::path::PathBuf,
        /// The last tick it reaches.
        ends_at: u64,
        /// The tick asked for.
        wanted: u64,
    },
    /// `bench --trace` names a trace with no racing frames to measure.
    #[error("{trace}: no racing frames to measure")]
    NoRacingFrames {
        /// The trace.
        trace: std::path::PathBuf,
    },
    /// A race could not be recorded, or its recording could not be kept.
    #[error(transparent)]
    Record(#[from] crate::input::recording::RecordError),
    /// A trace could not be opened or replayed.
    #[error(transparent)]
    Trace(#[from] crate::input::replay::ReplayError),
    /// An image could not be written.
    #[error(transparent)]
    Image(#[from] crate::shell::image_file::ImageFileError),
    /// `--quality auto` for a command that draws without a window.
    #[error(
        "{command}: --quality auto needs the window (it follows the frame time); name a preset: low, medium, high or ultra"
    )]
    AutoQualityWithoutWindow {
        /// The command: `render`, `replay --headless`.
        command: &'static str,
    },
    /// A soundtrack longer than a WAV file can hold.
    #[error("--audio: the race's sound would exceed the WAV format's 4 GiB (about {hours:.1} hours of racing)")]
    AudioTooLong {
        /// The most a WAV file holds, in hours of sound.
        hours: f64,
    },
    /// Standard output could not be written (a closed pipe).
    #[error("cannot write to standard output: {0}")]
    Stdout(#[source] std::io::Error),
    /// A stop signal ended the window as Quit would have; what was recorded is said with it.
    #[error("stopped by {signal}{}", kept.as_ref().map(|k| format!("; {k}")).unwrap_or_default())]
    Stopped {
        /// The signal.
        signal: crate::shell::stop::StopSignal,
        /// What became of the recording, when there was one.
        kept: Option<crate::input::recording::Kept>,
    },
    /// An output file named on the command line cannot be written there (checked before the work).
    #[error("cannot write {flag} {source}")]
    Output {
        /// The flag that named it (`--out`).
        flag: &'static str,
        /// What is wrong with the path.
        source: crate::userfile::UserFileError,
    },
}

/// Prints one line on stderr; a stderr that is gone (the terminal closed: SIGHUP) is no reason to panic
/// before the exit status is given, as `eprintln!` would.
pub(super) fn say(line: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// A window run that a stop signal ended is the [`CliError::Stopped`] that gives its exit status.
pub(super) fn stopped(ended: crate::shell::window::Ended) -> Result<(), CliError> {
    match ended {
        crate::shell::window::Ended::Closed => Ok(()),
        crate::shell::window::Ended::Signal(signal) => Err(CliError::Stopped { signal, kept: None }),
    }
}

impl CliError {
    /// The process's exit status for this error: 128 + the signal's number for a stop signal (the shell's
    /// convention), else 1.
    #[must_use]
    pub fn exit_status(&self) -> u8 {
        match self {
            CliError::Stopped { signal, .. } => signal.exit_status(),
            // Bad usage, as clap's own refusals.
            CliError::AutoQualityWithoutWindow { .. } => 2,
            _ => 1,
        }
    }
}

/// The `--assets DIR` flag the commands that race share.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct AssetsArg {
    /// A folder holding the race's assets (`track/`, `cars/`) to use instead of the ones built in
    /// (default: $SCANLINE_RACER_ASSETS, else an `assets` folder here or beside the build tree, else the
    /// built-in ones).
    #[arg(long, value_name = "DIR")]
    pub assets: Option<std::path::PathBuf>,
}

impl AssetsArg {
    /// Where the assets come from ([`crate::shell::race_scene::Assets::find`]).
    #[must_use]
    pub fn find(&self) -> crate::shell::race_scene::Assets {
        crate::shell::race_scene::Assets::find(self.assets.as_deref())
    }

    /// The race scene of the course the trace at `trace` was raced on (its header names it).
    pub fn scene_for_trace(&self, trace: &std::path::Path) -> Result<crate::shell::race_scene::RaceScene, CliError> {
        let (header, _) =
            crate::input::trace::TraceReader::open(trace).map_err(crate::input::replay::ReplayError::from)?;
        Ok(crate::shell::race_scene::RaceScene::open(&self.find(), &header.course)?)
    }
}

/// Refuses the output `out`, named by `flag`, when it leads to one of the command's `inputs` (checked
/// before anything is drawn or written).
pub(super) fn not_an_input(
    flag: &'static str,
    out: &std::path::Path,
    inputs: &crate::userfile::Inputs,
) -> Result<(), CliError> {
    inputs.check_output(out).map_err(|source| CliError::Output { flag, source })
}

/// What a race's assets are to the command, in messages.
pub(super) const ASSET_FILE: &str = "a file of the game's assets";

/// Makes `dir` (named by `flag`, to hold `what`) a folder the command can write into, before any long work:
/// creates it if missing and writes and removes a probe file, so a bad path fails at once in one line.
pub(super) fn output_folder(flag: &'static str, dir: &std::path::Path, what: &'static str) -> Result<(), CliError> {
    let path = dir.display().to_string();
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::NotAFolder { flag, path, what });
    }
    let fail = |file: &std::path::Path, e: std::io::Error| CliError::FolderNotWritable {
        flag,
        path: path.clone(),
        problem: crate::userfile::WriteProblem::of(e, file),
    };
    std::fs::create_dir_all(dir).map_err(|e| fail(dir, e))?;
    let (probe, _) = crate::userfile::create_temp_sibling(&dir.join("write-probe")).map_err(|e| fail(dir, e))?;
    std::fs::remove_file(&probe).map_err(|e| fail(&probe, e))
}
