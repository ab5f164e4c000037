//! The timing loop the A/B examples share: the best median of rounds of 40 frames, with each stage's best.

use std::time::Instant;

use scanline_racer::render::Stats;

/// What [`best_of`] measured.
pub struct Timing {
    /// The best round's median frame time, in ms.
    pub best: f64,
    /// The best transform, clip, order and fill times over every frame, in ms.
    pub stages: [f64; 4],
}

/// Calls `render` (one frame, returning its statistics) 40 times per round for `rounds` rounds.
pub fn best_of(rounds: usize, mut render: impl FnMut() -> Stats) -> Timing {
    let mut best = f64::INFINITY;
    let mut stages = [f64::INFINITY; 4];
    for _ in 0..rounds {
        let mut times: Vec<f64> = (0..40)
            .map(|_| {
                let t = Instant::now();
                let s = render();
                let ms = t.elapsed().as_secs_f64() * 1e3;
                for (b, v) in stages.iter_mut().zip([s.ms_transform, s.ms_clip, s.ms_order, s.ms_fill]) {
                    *b = b.min(v);
                }
                ms
            })
            .collect();
        times.sort_by(f64::total_cmp);
        best = best.min(times[times.len() / 2]);
    }
    Timing { best, stages }
}

/// An FNV-1a hash of a frame's pixels, to check that two builds drew the same.
pub fn frame_hash(frame: &[u32]) -> u64 {
    frame.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &p| (h ^ u64::from(p)).wrapping_mul(0x100_0000_01b3))
}
