//! The race simulation: a pure, deterministic, fixed-timestep function of the drivers' controls.
//!
//! `step(&mut World, &Controls)` is the whole interface; the clock and the accumulator live in the shell.
//! Nothing here reads a clock, uses OS randomness, iterates a hash map or renders.

pub mod ai;
pub mod car;
pub mod controls;
pub mod garage;
pub mod rules;
pub mod setup;
pub mod timestep;
pub mod track;
pub mod world;

pub use controls::Controls;
pub use setup::{Difficulty, Handling, Mode, RaceSetup};
pub use timestep::{DT, TICK_HZ};
pub use track::Track;
pub use world::{World, step};
