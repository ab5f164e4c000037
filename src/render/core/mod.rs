//! The bottom layer: plain records and number formats with no stage logic, which every stage above may
//! use and which use nothing above them.
//!
//! The renderer's inputs ([`options`] and its named [`quality`] steps, [`draw_list`], [`camera`], [`mesh`], [`texture`] with its [`mip`] chain), its outputs
//! ([`stats`], [`error`]), the fixed-point grid ([`fixed`]) and the coverage samples on it ([`samples`]), and the records the stages hand down: the
//! screen vertex ([`vertex`]), the polygon and its paint (`polygon`), the small triangle (`small`), the
//! set-up batches (`batch`) and the bands of the frame (`band`).

pub mod anisotropic;
pub(crate) mod band;
pub(crate) mod batch;
pub mod camera;
pub mod door;
pub mod draw_list;
pub mod error;
pub mod filter;
pub mod fixed;
pub mod mesh;
pub mod mip;
pub mod options;
pub(crate) mod polygon;
pub mod quality;
pub mod samples;
pub(crate) mod small;
pub mod stats;
#[cfg(test)]
pub(crate) mod test_rng;
pub mod texture;
pub mod vertex;
