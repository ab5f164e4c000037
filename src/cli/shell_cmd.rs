//! `scanline-racer completions SHELL` and `scanline-racer man`: shell completions and the man page,
//! generated from the command-line definitions, printed on stdout.
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
