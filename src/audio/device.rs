//! The real audio path: the default output device through cpal, fed from a lock-free [`Ring`].
//!
//! The game thread renders a tick of samples after each simulation tick and [`Output::push`]es them; the
//! device's callback takes what is there and plays silence for what is not. Neither side ever waits: the
//! push drops what does not fit, the callback never blocks on the game. The stream asks for a 10 ms
//! device buffer (falling back to the device's default size where a fixed size is refused), and the ring
//! holds at most [`RING_SECONDS`] (20 ms), so sound lags the picture by at most about 30 ms plus what the
//! game queues beyond the ring (two ticks).
//! With no device (a server, a container, CI) [`open`] returns an [`AudioError`] for the caller to say once
//! and run silent.

use std::sync::Arc;

use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
use thiserror::Error;

use super::format::{CHANNELS, SAMPLE_RATE};
use super::ring::Ring;

/// Device buffer asked for (frames): 10 ms at 48 kHz.
pub const DEVICE_FRAMES: u32 = 480;
/// Most sound the ring holds ahead of the device (seconds): the game fills it once a frame (two ticks at
/// 60 Hz, 16.7 ms), so 20 ms covers a frame with a little to spare while keeping the sound close to the
/// picture.
pub const RING_SECONDS: f32 = 0.02;

/// Why there is no sound.
#[derive(Debug, Error)]
pub enum AudioError {
    /// Neither a sound card (`/dev/snd`) nor a PulseAudio or PipeWire server's socket exists: nothing was
    /// asked of the system (ALSA would print a dozen lines of its own looking for a card).
    #[error("no sound card (/dev/snd) and no PulseAudio server")]
    NothingHere,
    /// The system has no default output device (no sound card, no sound server).
    #[error("no audio output device")]
    NoDevice,
    /// The device refused a 48 kHz stereo stream of floats.
    #[error("audio device '{device}' cannot play 48 kHz stereo: {source}")]
    Stream {
        /// The device's name as the system gives it.
        device: String,
        /// cpal's error.
        source: cpal::Error,
    },
    /// The stream was made but would not start.
    #[error("audio device '{device}' would not start: {source}")]
    Play {
        /// The device's name as the system gives it.
        device: String,
        /// cpal's error.
        source: cpal::Error,
    },
}

/// A playing output stream and the ring that feeds it; dropping it stops the sound.
pub struct Output {
    ring: Arc<Ring>,
    /// Kept alive for as long as the sound should play.
    _stream: cpal::Stream,
}

impl std::fmt::Debug for Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Output").field("queued", &self.ring.len()).finish_non_exhaustive()
    }
}

impl Output {
    /// Queues interleaved stereo samples for the device; returns how many fitted (the rest are dropped, so
    /// the game never waits for the device).
    pub fn push(&self, samples: &[f32]) -> usize {
        self.ring.push(samples)
    }

    /// Samples queued and not yet played: the game can skip rendering when it is far ahead.
    #[must_use]
    pub fn queued(&self) -> usize {
        self.ring.len()
    }

    /// Samples the device asked for and did not get (played as silence) since the stream started.
    #[must_use]
    pub fn underruns(&self) -> u64 {
        self.ring.underruns()
    }
}

/// The samples a ring of [`RING_SECONDS`] holds.
#[must_use]
pub fn ring_capacity() -> usize {
    (RING_SECONDS * SAMPLE_RATE as f32) as usize * CHANNELS
}

/// Whether this system has anything that could play sound: a sound card under `/dev/snd`, or a PulseAudio
/// server (or PipeWire's, which serves the same socket): `$PULSE_SERVER`, `$XDG_RUNTIME_DIR/pulse/native`,
/// `/run/user/*/pulse/native`, or the system-wide `/run/pulse/native`.
///
/// Why: with neither, ALSA (under cpal) still tries its cards and prints many `ALSA lib ...` lines to
/// stderr; asking nothing keeps the game's "no audio" report to its one line.
#[must_use]
pub fn anything_to_open() -> bool {
    use std::path::{Path, PathBuf};
    if Path::new("/dev/snd").is_dir() || std::env::var_os("PULSE_SERVER").is_some_and(|s| !s.is_empty()) {
        return true;
    }
    let mut sockets: Vec<PathBuf> = vec!["/run/pulse/native".into(), "/var/run/pulse/native".into()];
    if let Some(dir) = std::env::var_os("XDG_RUNTIME_DIR").filter(|d| !d.is_empty()) {
        sockets.push(PathBuf::from(dir).join("pulse/native"));
    }
    if let Ok(users) = std::fs::read_dir("/run/user") {
        sockets.extend(users.filter_map(Result::ok).map(|u| u.path().join("pulse/native")));
    }
    sockets.iter().any(|p| p.exists())
}

/// Opens the default output device at 48 kHz stereo and starts it playing silence until samples are pushed;
/// [`AudioError::NothingHere`] at once, without asking the system, when [`anything_to_open`] finds nothing.
pub fn open() -> Result<Output, AudioError> {
    if !anything_to_open() {
        return Err(AudioError::NothingHere);
    }
    let host = cpal::default_host();
    let device = host.default_output_device().ok_or(AudioError::NoDevice)?;
    let name = device.description().map_or_else(|_| "default".to_string(), |d| d.to_string());
    let ring = Ring::new(ring_capacity());
    let build = |buffer_size| {
        let config = cpal::StreamConfig { channels: CHANNELS as u16, sample_rate: SAMPLE_RATE, buffer_size };
        let feed = Arc::clone(&ring);
        device.build_output_stream::<f32, _, _>(
            config,
            move |data: &mut [f32], _: &cpal::OutputCallbackInfo| {
                feed.pop_into(data);
            },
            // A device lost mid-game leaves the game silent; the callback has nowhere to report to.
            |_err| {},
            None,
        )
    };
    let stream = build(cpal::BufferSize::Fixed(DEVICE_FRAMES))
        .or_else(|_| build(cpal::BufferSize::Default))
        .map_err(|source| AudioError::Stream { device: name.clone(), source })?;
    stream.play().map_err(|source| AudioError::Play { device: name, source })?;
    Ok(Output { ring, _stream: stream })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn opening_gives_an_output_or_a_one_line_error() {
        // Either way the call returns: no device is an error to print, never a panic or a hang.
        match open() {
            Ok(out) => {
                assert!(out.push(&[0.0; 800]) > 0);
                assert!(out.queued() <= ring_capacity());
            }
            Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
        }
        assert_eq!(ring_capacity(), 1920);
    }
}
