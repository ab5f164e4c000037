//! WAV encoding: 16-bit PCM, 48 kHz, stereo, written by hand (a 44-byte header and the samples).
//!
//! The conversion rounds each sample the same way on every machine, so a soundtrack's file is as
//! reproducible as its samples.

use super::format::{CHANNELS, SAMPLE_RATE};

/// Bytes of the header before the samples.
pub const HEADER_BYTES: usize = 44;

/// A sample in `[-1, 1]` as a 16-bit PCM value (clamped; NaN is silence).
#[must_use]
pub fn to_i16(x: f32) -> i16 {
    if x.is_nan() {
        return 0;
    }
    (x.clamp(-1.0, 1.0) * 32767.0).round() as i16
}

/// The header of a WAV file holding `frames` stereo frames of 16-bit PCM at [`SAMPLE_RATE`]; `None` when
/// the data would not fit the format's 4 GiB.
#[must_use]
pub fn header(frames: usize) -> Option<[u8; HEADER_BYTES]> {
    let block = CHANNELS * 2;
    let data = u32::try_from(frames.checked_mul(block)?).ok()?;
    let riff = data.checked_add(36)?;
    if data as usize + HEADER_BYTES > MAX_BYTES {
        return None;
    }
    let mut h = [0u8; HEADER_BYTES];
    let mut at = 0;
    let mut put = |bytes: &[u8]| {
        h[at..at + bytes.len()].copy_from_slice(bytes);
        at += bytes.len();
    };
    put(b"RIFF");
    put(&riff.to_le_bytes());
    put(b"WAVEfmt ");
    put(&16u32.to_le_bytes());
    put(&1u16.to_le_bytes()); // PCM
    put(&(CHANNELS as u16).to_le_bytes());
    put(&SAMPLE_RATE.to_le_bytes());
    put(&(SAMPLE_RATE * block as u32).to_le_bytes());
    put(&(block as u16).to_le_bytes());
    put(&16u16.to_le_bytes());
    put(b"data");
    put(&data.to_le_bytes());
    Some(h)
}

/// The most bytes a WAV file can hold (its sizes are 32-bit), header included.
pub const MAX_BYTES: usize = u32::MAX as usize;

/// Bytes of sound per second.
#[must_use]
pub fn bytes_per_second() -> f64 {
    f64::from(SAMPLE_RATE) * (CHANNELS * 2) as f64
}

/// Appends interleaved `samples` to a WAV file's bytes as 16-bit little-endian PCM.
pub fn append(samples: &[f32], out: &mut Vec<u8>) {
    out.reserve(2 * samples.len());
    for &x in samples {
        out.extend_from_slice(&to_i16(x).to_le_bytes());
    }
}

/// A whole WAV file of interleaved stereo `samples`; `None` when it would exceed the format's 4 GiB.
#[must_use]
pub fn encode(samples: &[f32]) -> Option<Vec<u8>> {
    let head = header(samples.len() / CHANNELS)?;
    let mut out = Vec::with_capacity(HEADER_BYTES + 2 * samples.len());
    out.extend_from_slice(&head);
    append(&samples[..samples.len() / CHANNELS * CHANNELS], &mut out);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encodes_a_canonical_pcm_file() {
        let bytes = encode(&[0.0, 1.0, -1.0, 0.5, 2.0]).expect("small");
        assert_eq!(&bytes[0..4], b"RIFF");
        assert_eq!(u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]), 36 + 8);
        assert_eq!(&bytes[8..16], b"WAVEfmt ");
        assert_eq!(u32::from_le_bytes([bytes[24], bytes[25], bytes[26], bytes[27]]), 48_000);
        assert_eq!(bytes.len(), 44 + 8, "a half frame is dropped");
        let s: Vec<i16> = bytes[44..].chunks(2).map(|c| i16::from_le_bytes([c[0], c[1]])).collect();
        assert_eq!(s, [0, 32767, -32767, 16384]);
        assert_eq!(to_i16(f32::NAN), 0);
        assert_eq!(to_i16(9.0), 32767);
    }
}
