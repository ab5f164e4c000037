//! The real audio path: the default output device through cpal (a PulseAudio or PipeWire server spoken to
//! directly where one runs, ALSA otherwise), fed from a lock-free [`Ring`].
//!
//! The game thread renders a tick of samples after each simulation tick and [`Output::push`]es them; the
//! device's callback takes what is there and plays silence for what is not. Neither side ever waits: the
//! push drops what does not fit, the callback never blocks on the game.
//!
//! The stream asks for periods of [`DEVICE_FRAMES`] (21 ms; cpal keeps two of them), falling
//! back to the device's default size where a fixed size is refused. Why so many: through PulseAudio's
//! ALSA plugin, periods of 10 ms and less underran every 15-60 s even for a callback that only copies, and
//! each underrun cost about 2 s of silence while the stream recovered. The ring holds at most one period
//! as the stream really made it ([`Output::limit`]) plus [`LEAD_FRAMES`] (a frame's two ticks), so sound
//! lags the picture by at most the device's two periods, that, and the two ticks the game queues beyond it.
//! With no device (a server, a container, CI) [`open`] returns an [`AudioError`] for the caller to say once
//! and run silent.

use std::sync::Arc;

use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
use thiserror::Error;

use super::format::{CHANNELS, FRAMES_PER_TICK, SAMPLE_RATE};
use super::ring::Ring;

/// Device period asked for (frames): 21 ms at 48 kHz.
pub const DEVICE_FRAMES: u32 = 1024;
/// Frames the ring may hold beyond one device period: the game fills it once a frame, two ticks at 60 Hz.
pub const LEAD_FRAMES: usize = 2 * FRAMES_PER_TICK;
/// Largest device period the ring makes room for (frames, 85 ms); a device that asks more per callback
/// gets the rest as silence.
pub const MAX_PERIOD_FRAMES: usize = 4096;

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
    /// A PulseAudio (or PipeWire) socket exists but no server answered on it, and there is no sound card.
    #[error("the PulseAudio server's socket is there but no server answered on it")]
    NoServer,
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
    /// Most samples queued in the ring: one period of the stream plus [`LEAD_FRAMES`].
    limit: usize,
    /// Kept alive for as long as the sound should play.
    _stream: cpal::Stream,
}

impl std::fmt::Debug for Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Output").field("queued", &self.ring.len()).field("limit", &self.limit).finish_non_exhaustive()
    }
}

impl Output {
    /// Queues interleaved stereo samples for the device, up to [`Output::limit`] queued; returns how many
    /// fitted (the caller keeps or drops the rest, so the game never waits for the device).
    pub fn push(&self, samples: &[f32]) -> usize {
        let room = self.limit.saturating_sub(self.ring.len());
        self.ring.push(&samples[..samples.len().min(room)])
    }

    /// Most samples queued for the device at once: one period of the stream as it was made, plus
    /// [`LEAD_FRAMES`]; more would only delay the sound.
    #[must_use]
    pub fn limit(&self) -> usize {
        self.limit
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

/// The samples the ring is made with: room for the largest period and the lead.
#[must_use]
pub fn ring_capacity() -> usize {
    (MAX_PERIOD_FRAMES + LEAD_FRAMES) * CHANNELS
}

/// The most samples queued for a stream whose callback asks `period` frames at a time (`None`: unknown, taken
/// as [`DEVICE_FRAMES`]).
#[must_use]
pub fn queue_limit(period: Option<u32>) -> usize {
    let period = period.map_or(DEVICE_FRAMES as usize, |p| p as usize).clamp(FRAMES_PER_TICK / 4, MAX_PERIOD_FRAMES);
    (period + LEAD_FRAMES) * CHANNELS
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
    // A PulseAudio server (or PipeWire's) is spoken to directly when there is one: through ALSA's pulse
    // plugin an underrun cost about 2 s of silence (the plugin waits for a timing update, at intervals that
    // double from 10 ms, before it asks for samples again), and so did the start.
    // (cpal's default host would try the server again before ALSA: a server that did not answer would
    // then hold the first frame twice.)
    #[cfg(target_os = "linux")]
    {
        let pulse = cpal::host_from_id(cpal::HostId::PulseAudio).map_err(|_| AudioError::NoServer);
        let why = match pulse.and_then(|h| open_on(&h)) {
            Ok(out) => return Ok(out),
            Err(e) => e,
        };
        // Without a sound card ALSA could only reach the same server (and would print its own lines).
        if !std::path::Path::new("/dev/snd").is_dir() {
            return Err(why);
        }
        let alsa = cpal::host_from_id(cpal::HostId::Alsa).map_err(|_| AudioError::NoDevice)?;
        open_on(&alsa)
    }
    #[cfg(not(target_os = "linux"))]
    open_on(&cpal::default_host())
}

/// Opens `host`'s default output device at 48 kHz stereo, playing what the ring is given.
fn open_on(host: &cpal::Host) -> Result<Output, AudioError> {
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
    let limit = queue_limit(stream.buffer_size().ok());
    Ok(Output { ring, limit, _stream: stream })
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
                // The device may take some meanwhile, never more than a period: the ring fills to the limit only.
                let taken = out.push(&vec![0.0; ring_capacity()]);
                assert!(taken > 0 && taken <= out.limit(), "{taken} of {}", out.limit());
                assert!(out.queued() <= out.limit() && out.limit() <= ring_capacity());
            }
            Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
        }
    }

    #[test]
    fn the_queue_holds_one_period_and_a_frame_of_ticks() {
        assert_eq!(queue_limit(Some(682)), (682 + 800) * 2);
        assert_eq!(queue_limit(None), (1024 + 800) * 2);
        assert_eq!(queue_limit(Some(1 << 20)), ring_capacity(), "a huge period is capped at the ring");
        assert_eq!(queue_limit(Some(0)), (100 + 800) * 2, "a nonsense period still queues a frame");
    }
}
