//! The temporal-stability half of the sweep: a configuration drawn over consecutive frames on one renderer
//! that keeps its LOD history (reset only at the sequence's start, as the game does at a restart), measured
//! against the reference sequence: shimmer RMS, shimmering pixels and FLIP mean over the frames.

use super::frames::BenchFrame;
use crate::measure::{Shimmer, flip, reference_frame};
use crate::render::{DrawList, RenderError, RenderOptions, Renderer, SKY_BLUE};

/// What one configuration measured over the sequence.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SequenceMeasure {
    /// Mean FLIP against the reference over the sequence's frames.
    pub flip_mean: f64,
    /// RMS (0-255) of the frame-to-frame change the reference does not have ([`Shimmer::rms`]).
    pub shimmer_rms: f64,
    /// Share of shimmering pixels over the frame pairs, in percent ([`Shimmer::shimmering_pct`]).
    pub shimmer_pct: f64,
}

/// The reference frames of the sequence at one size, kept while configurations of that size follow.
#[derive(Debug, Default)]
pub struct SequenceReferences {
    size: (usize, usize),
    frames: Vec<Vec<u32>>,
}

/// Draws `sequence` with `options` at `size` on `renderer`, its LOD history reset once at the start, and
/// measures it against the reference sequence (made on first use at each size and kept in `references`).
/// An empty sequence measures all zeros.
pub fn measure_sequence<'s>(
    renderer: &mut Renderer,
    sequence: &'s [BenchFrame],
    list_for: impl Fn(&'s BenchFrame) -> DrawList<'s>,
    options: &RenderOptions,
    size: (usize, usize),
    references: &mut SequenceReferences,
) -> Result<SequenceMeasure, RenderError> {
    let (w, h) = size;
    if references.size != size || references.frames.len() != sequence.len() {
        references.frames.clear();
        for f in sequence {
            references.frames.push(reference_frame(&f.camera, &list_for(f), w, h, SKY_BLUE)?);
        }
        references.size = size;
    }
    renderer.reset_lod();
    let (mut shimmer, mut flip_sum) = (Shimmer::default(), 0.0);
    let mut img = vec![0u32; w * h];
    for (f, reference) in sequence.iter().zip(&references.frames) {
        renderer.render(&mut img, w, h, &f.camera, &list_for(f), options)?;
        shimmer.push(reference, &img);
        flip_sum += flip(reference, &img, w, h).map_or(0.0, |f| f64::from(f.mean));
    }
    Ok(SequenceMeasure {
        flip_mean: flip_sum / sequence.len().max(1) as f64,
        shimmer_rms: shimmer.rms(),
        shimmer_pct: shimmer.shimmering_pct(),
    })
}
