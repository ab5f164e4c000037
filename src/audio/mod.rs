//! Sound: engines, tyres, surfaces, impacts and the race's signals, synthesised from the simulation's world
//! states, and the audio device that plays them.
//!
//! The sound of a race is a pure function of its worlds, like its frames: [`Mixer::advance`] takes each
//! tick's world, [`Mixer::render`] appends that tick's [`FRAMES_PER_TICK`] stereo frames at [`SAMPLE_RATE`].
//! No clock, no randomness but seeded generators, `libm` for every transcendental function, so a headless
//! replay writes the same WAV bits on every run and every machine (`wav`). `device` plays the same samples
//! on the default output device through a ring buffer the game thread fills and never waits on.
//!
//! - `dsp`: sine table, seeded noise, filters, per-tick ramps.
//! - `engine`: the gearbox and engine-speed curve inferred from a car's speed and acceleration.
//! - `voice`: one car's engine, tyre squeal and kerb/grass rumble, panned, attenuated and Doppler-shifted.
//! - `events`: impacts detected from state changes, countdown beeps, the finish chime, menu clicks.
//! - `mixer`: the sum, volume and mute, limiter; the end's fade.
//! - `wav`: 16-bit PCM WAV encoding.
//! - `ring` and `device`: the lock-free sample ring and the cpal output stream.

pub mod device;
pub mod dsp;
pub mod engine;
pub mod events;
pub mod mixer;
pub mod ring;
pub mod voice;
pub mod wav;

pub use device::{AudioError, Output, open};
pub use mixer::Mixer;

/// Samples per second per channel.
pub const SAMPLE_RATE: u32 = 48_000;
/// Channels (interleaved left, right).
pub const CHANNELS: usize = 2;
/// Stereo frames per simulation tick: 48,000 / 120 = 400, exactly, so ticks and samples never drift.
pub const FRAMES_PER_TICK: usize = (SAMPLE_RATE / crate::game::TICK_HZ) as usize;

const _: () = assert!(SAMPLE_RATE.is_multiple_of(crate::game::TICK_HZ), "a tick must be a whole number of samples");
