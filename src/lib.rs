//! scanline-racer: an arcade racing demo whose every pixel comes from its own CPU scanline renderer.
//!
//! Modules and who may use whom are described in `ARCHITECTURE.md`: [`render`] is the renderer and depends
//! on nothing else here; [`asset`] loads glTF files into the renderer's meshes and textures; [`cli`] is the
//! command-line shell.

pub mod asset;
pub mod audio;
pub mod bench;
pub mod cli;
pub mod game;
pub mod input;
pub mod measure;
pub mod render;
pub mod shell;
pub mod userfile;
