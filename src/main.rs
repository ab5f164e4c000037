//! The `scanline-racer` executable: see `scanline-racer --help`.

fn main() -> std::process::ExitCode {
    scanline_racer::cli::main()
}
