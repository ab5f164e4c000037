//! `scanline-racer completions SHELL` and `scanline-racer man`: shell completions and the man page,
//! generated from the command-line definitions, printed on stdout; and `scanline-racer courses`, the list
//! of courses `play --course` takes.
//!
//! Why generated: written by hand they drift from the flags; from clap's definitions every flag, value
//! and help line is the one `--help` shows.

use std::io::Write;

use clap::Args;

use super::error::CliError;

/// Arguments of `completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    pub shell: clap_complete::Shell,
}

/// Arguments of `courses`.
#[derive(Debug, Args)]
pub struct CoursesArgs {
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

/// Prints one line per course: its name, lap length, title and what it is like.
pub fn courses_command(args: &CoursesArgs) -> Result<(), CliError> {
    let assets = args.assets.find();
    let courses = assets.courses();
    if courses.is_empty() {
        return Err(CliError::NoCourses {
            place: match &assets {
                crate::shell::race_scene::Assets::Folder(dir) => dir.join("track").display().to_string(),
                crate::shell::race_scene::Assets::BuiltIn => "the built-in assets".to_string(),
            },
        });
    }
    let mut out = String::new();
    for c in &courses {
        let about = if c.about.is_empty() { String::new() } else { format!(": {}", c.about) };
        out.push_str(&format!("{:<12} {:>5.2} km  {}{about}\n", c.name, c.length_m / 1000.0, c.title));
    }
    print(out.as_bytes())
}

/// Prints one line per car of the garage: its number (for --car), name and handling figures.
pub fn cars_command() -> Result<(), CliError> {
    let mut out = String::from("car  name           top speed  0-100 km/h  braking  grip\n");
    for (i, c) in crate::game::garage::GARAGE.iter().enumerate() {
        out.push_str(&format!(
            "{:<4} {:<14} {:>5.0} km/h  {:>6.1} s  {:>5.1} g  {:>4.2} g\n",
            i + 1,
            c.name,
            c.top_speed * 3.6,
            c.zero_to_100(),
            c.brake / 9.81,
            c.grip / 9.81
        ));
    }
    print(out.as_bytes())
}

/// Prints the completion script of the command line `cli` for `args.shell` (for bash: `scanline-racer
/// completions bash > ~/.local/share/bash-completion/completions/scanline-racer`).
pub fn completions_command(args: &CompletionsArgs, mut cli: clap::Command) -> Result<(), CliError> {
    let mut out = Vec::new();
    clap_complete::generate(args.shell, &mut cli, "scanline-racer", &mut out);
    print(&out)
}

/// Prints the man page of the command line `cli` in roff (`scanline-racer man > scanline-racer.1`, then
/// `man ./scanline-racer.1`).
pub fn man_command(cli: clap::Command) -> Result<(), CliError> {
    let mut out = Vec::new();
    clap_mangen::Man::new(cli).render(&mut out).map_err(CliError::Stdout)?;
    print(&out)
}

/// Writes `bytes` to stdout; a closed pipe (`| head`) is an error in one line, not a panic.
fn print(bytes: &[u8]) -> Result<(), CliError> {
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(bytes).and_then(|()| stdout.flush()).map_err(CliError::Stdout)
}
