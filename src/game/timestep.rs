//! The simulation's fixed timestep: how many ticks make a second.
//!
//! Its own file because both the world's step and the race rules (countdown, lap times) count in ticks,
//! and neither should import the other for it.

/// Simulation ticks per second.
pub const TICK_HZ: u32 = 120;
/// Seconds per tick.
pub const DT: f32 = 1.0 / TICK_HZ as f32;
