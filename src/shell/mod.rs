//! The application shell: the window, presentation, and frame output. The only code that touches winit and
//! softbuffer; it hands the renderer a plain `&mut [u32]` and copies the result to the screen.

pub mod auto_quality;
pub mod built_in;
pub mod course;
pub mod debug_overlay;
pub mod image_file;
pub mod keys;
pub mod pacing;
pub mod race;
pub mod race_scene;
pub mod records;
pub mod settings;
pub mod stop;
pub mod ui;
pub mod viewer;
pub mod window;
mod x11_lost;
