//! Sound: engines, tyres, surfaces, impacts and the race's signals, synthesised from the simulation's world
//! states, and the audio device that plays them.
//!
//! The sound of a race is a pure function of its worlds, like its frames: [`Mixer::advance`] takes each
//! tick's world, [`Mixer::render`] appends that tick's [`FRAMES_PER_TICK`] stereo frames at [`SAMPLE_RATE`].
//! No clock, no randomness but seeded generators, `libm` for every transcendental function, so a headless
//! replay writes the same WAV bits on every run and every machine (`wav`). `device` plays the same samples
//! on the default output device through a ring buffer the game thread fills and never waits on.
//!
//! - `format`: the sample rate, channels and samples per tick every part counts in.
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
pub mod format;
pub mod mixer;
pub mod ring;
pub mod voice;
pub mod wav;

pub use device::{AudioError, Output, open};
pub use format::{CHANNELS, FRAMES_PER_TICK, SAMPLE_RATE};
pub use mixer::Mixer;
