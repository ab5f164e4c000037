//! The sound's format: the sample rate, the channels and the samples per simulation tick, which every part
//! of the audio counts in (kept below them, so no part imports the module that ties them together).

/// Samples per second per channel.
pub const SAMPLE_RATE: u32 = 48_000;
/// Channels (interleaved left, right).
pub const CHANNELS: usize = 2;
/// Stereo frames per simulation tick: 48,000 / 120 = 400, exactly, so ticks and samples never drift.
pub const FRAMES_PER_TICK: usize = (SAMPLE_RATE / crate::game::TICK_HZ) as usize;

const _: () = assert!(SAMPLE_RATE.is_multiple_of(crate::game::TICK_HZ), "a tick must be a whole number of samples");
