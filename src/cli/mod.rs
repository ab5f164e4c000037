//! The command-line shell: parses arguments, runs a command, reports errors in one line.
//!
//! This is the only place where the loader, the renderer and output files meet. Errors go to stderr as
//! `scanline-racer: error: ...` with exit status 1; bad usage exits with 2 (clap's convention).

mod bench_cmd;
mod error;
mod export_cmd;
mod picture;
mod play_cmd;
mod render_cmd;
mod replay_cmd;
mod shell_cmd;
pub mod values;

use std::process::ExitCode;

use clap::{CommandFactory, Parser, Subcommand};

pub use bench_cmd::{BenchArgs, bench_command};
pub use error::CliError;
use error::say;
pub use export_cmd::{ExportArgs, export_command};
pub use play_cmd::{PlayArgs, play_command};
pub use render_cmd::{RenderArgs, render_command};
pub use replay_cmd::{ReplayArgs, ReplaySummary, replay_command, replay_headless};
pub use shell_cmd::{CompletionsArgs, CoursesArgs, cars_command, completions_command, courses_command, man_command};

/// Top-level arguments.
#[derive(Debug, Parser)]
#[command(name = "scanline-racer", version, about = "An arcade racer drawn by its own CPU scanline renderer")]
pub struct Cli {
    /// The command to run.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the game window and race (the default); with --scene or --demo, fly a camera around a scene.
    Play(PlayArgs),
    /// Draw a glTF scene to a PNG with the software renderer (headless).
    Render(RenderArgs),
    /// Replay a recorded race, in the window or headless (`--headless --frames DIR`).
    Replay(ReplayArgs),
    /// Write what one frame of a replay draws (world-space triangles after LOD, textures, camera) as GLB.
    ExportFrame(ExportArgs),
    /// Chart speed against accuracy for every method and setting over a demo replay (CSV, SVG, PNG).
    Bench(BenchArgs),
    /// List the courses: name (for --course), lap length, title and what each is like.
    Courses(CoursesArgs),
    /// List the cars: number (for --car), name and handling (top speed, acceleration, braking, grip).
    Cars,
    /// Print the shell completion script for bash, zsh, fish, elvish or powershell.
    Completions(CompletionsArgs),
    /// Print the man page (roff).
    Man,
}

/// Parses the process arguments, runs the command and returns the exit status.
#[must_use]
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render_command(&args),
        Some(Command::Play(args)) => play_command(args),
        Some(Command::Replay(args)) => replay_command(&args),
        Some(Command::Bench(args)) => bench_command(&args),
        Some(Command::ExportFrame(args)) => export_command(&args),
        Some(Command::Courses(args)) => courses_command(&args),
        Some(Command::Cars) => cars_command(),
        Some(Command::Completions(args)) => completions_command(&args, Cli::command()),
        Some(Command::Man) => man_command(Cli::command()),
        None => play_command(PlayArgs::default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // A stop is no error: the user asked for it.
        Err(e @ CliError::Stopped { .. }) => {
            say(&format!("scanline-racer: {e}"));
            ExitCode::from(e.exit_status())
        }
        Err(e) => {
            say(&format!("scanline-racer: error: {e}"));
            ExitCode::from(e.exit_status())
        }
    }
}
