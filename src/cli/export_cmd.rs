//! `scanline-racer export-frame TRACE --tick N --out FRAME.glb`: what one frame of a replay draws, as glTF.

use std::path::PathBuf;

use clap::Args;

use super::error::CliError;
use super::values;
use crate::asset::export::export_glb;
use crate::input::replay::Replay;
use crate::render::{RenderOptions, Renderer};
use crate::shell::race_scene::{View, camera_for};

/// Arguments of `export-frame`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The trace to replay.
    pub trace: PathBuf,
    /// The tick whose frame is exported.
    #[arg(long)]
    pub tick: u64,
    /// The GLB file to write (its name ends in .glb).
    #[arg(long, value_parser = values::glb_path())]
    pub out: PathBuf,
    /// Frame width (sets the camera's aspect and the LOD choice), 1 to 16384.
    #[arg(long, default_value_t = 1280, value_parser = values::side(values::MAX_SIDE))]
    pub width: usize,
    /// Frame height, 1 to 16384.
    #[arg(long, default_value_t = 720, value_parser = values::side(values::MAX_SIDE))]
    pub height: usize,
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

/// Runs `export-frame`; prints what was written.
pub fn export_command(args: &ExportArgs) -> Result<(), CliError> {
    crate::userfile::check_output(&args.out).map_err(|source| CliError::Output { flag: "--out", source })?;
    let scene = args.assets.scene_for_trace(&args.trace)?;
    let mut inputs = crate::userfile::Inputs::new();
    inputs.add(&args.trace, "the trace");
    inputs.add_all(&scene.scene().files, super::error::ASSET_FILE);
    super::error::not_an_input("--out", &args.out, &inputs)?;
    let mut replay = Replay::open(&args.trace, scene.track.clone())?;
    while replay.world.tick < args.tick {
        if !replay.advance()? {
            return Err(CliError::TraceTooShort {
                trace: args.trace.clone(),
                ends_at: replay.world.tick,
                wanted: args.tick,
            });
        }
    }
    let camera = camera_for(&replay.world, View::ChaseNear);
    let instances = scene.instances(&replay.world, None);
    let list = scene.draw_list(&instances);
    let options = RenderOptions::default();
    let lod = Renderer::new().frame_lod(args.width, args.height, &camera, &list, &options);
    let chosen: Vec<Option<usize>> = lod.into_iter().map(|m| m.map(|(mesh, _)| mesh)).collect();
    let (bytes, summary) = export_glb(&list, &chosen, &camera, (args.width, args.height))?;
    crate::userfile::replace_atomically(&args.out, &bytes).map_err(CliError::Write)?;
    eprintln!(
        "wrote {} (tick {}, {}x{}: {} instances, {} triangles, {} materials, {} bytes)",
        args.out.display(),
        args.tick,
        args.width,
        args.height,
        summary.instances,
        summary.triangles,
        summary.primitives,
        bytes.len()
    );
    Ok(())
}
