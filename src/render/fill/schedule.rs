//! Which band each thread draws next: every thread takes the next band not yet begun from one queue, the
//! bands that cost most in the last frame of the same layout first.
//!
//! Why: a frame's bands cost very different amounts (the horizon's many small polygons against the sky's
//! clear), and the frame ends when its last band does. Drawn in screen order, a costly band near the end
//! of a thread's share left the other thread idle for up to that band's time; costliest first, the last
//! bands taken are the cheapest, so the threads finish within about one cheap band of each other (the
//! longest-processing-time-first rule). Successive frames of a race look alike, so the last frame's time
//! of each band is its cost. Which thread draws a band never changes its pixels (see [`super`]), so the
//! order is free to follow timing.

use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Instant;

use rayon::iter::{IndexedParallelIterator, IntoParallelIterator, ParallelIterator};

use super::bands::FillContext;
use super::row::SpanCounts;
use crate::render::core::band::{Band, FrameLayout};

/// The last frame's time of each band, for the layout it was drawn in.
#[derive(Debug, Default)]
pub(crate) struct BandCosts {
    /// The layout the times are of (`None` before the first frame on several threads).
    layout: Option<FrameLayout>,
    /// Nanoseconds each band took, by band index.
    ns: Vec<u64>,
}

impl BandCosts {
    /// The order in which `count` bands of `layout` are handed out: by last frame's time, costliest first
    /// (ties in screen order); in screen order when there is no last frame of this layout.
    pub(crate) fn order(&self, layout: FrameLayout, count: usize) -> Vec<usize> {
        let mut order: Vec<usize> = (0..count).collect();
        if self.layout == Some(layout) && self.ns.len() == count {
            // Stable: equal times keep screen order.
            order.sort_by_key(|&i| std::cmp::Reverse(self.ns[i]));
        }
        order
    }

    /// Draws `bands` (of `layout`, in screen order) on `layout.threads` threads of the current pool, each
    /// thread taking the next band of [`Self::order`] not yet begun; keeps each band's time for the next
    /// frame. Returns the counts of all the bands' spans.
    pub(crate) fn draw(&mut self, ctx: &FillContext<'_>, bands: Vec<Band<'_>>, layout: FrameLayout) -> SpanCounts {
        let count = bands.len();
        let order = self.order(layout, count);
        let mut slots: Vec<Option<Band<'_>>> = bands.into_iter().map(Some).collect();
        // Each queue entry is taken by exactly one thread (the index is claimed atomically); the lock only
        // moves the band's rows to it.
        let queue: Vec<Mutex<Option<(usize, Band<'_>)>>> =
            order.iter().map(|&i| Mutex::new(slots.get_mut(i).and_then(Option::take).map(|b| (i, b)))).collect();
        let next = AtomicUsize::new(0);
        let times: Vec<AtomicU64> = (0..count).map(|_| AtomicU64::new(0)).collect();
        // One task per thread: a thread not yet awake when the others have taken every band finds the queue
        // empty, so no band waits for it.
        let counts = (0..layout.threads)
            .into_par_iter()
            .with_max_len(1)
            .map(|_| {
                let mut counts = SpanCounts::default();
                while let Some(entry) = queue.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let Some((i, band)) = entry.lock().ok().and_then(|mut e| e.take()) else { continue };
                    let t = Instant::now();
                    counts += ctx.fill_band(band, i);
                    if let Some(slot) = times.get(i) {
                        slot.store(u64::try_from(t.elapsed().as_nanos()).unwrap_or(u64::MAX), Ordering::Relaxed);
                    }
                }
                counts
            })
            .reduce(SpanCounts::default, |a, b| a + b);
        self.layout = Some(layout);
        self.ns = times.into_iter().map(AtomicU64::into_inner).collect();
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout(height: usize) -> FrameLayout {
        FrameLayout::new(64, height, 2)
    }

    #[test]
    fn bands_go_costliest_first_with_ties_in_screen_order_and_in_screen_order_without_times() {
        let mut c = BandCosts::default();
        assert_eq!(c.order(layout(120), 4), vec![0, 1, 2, 3], "no last frame");
        c.layout = Some(layout(120));
        c.ns = vec![5, 40, 5, 90];
        assert_eq!(c.order(layout(120), 4), vec![3, 1, 0, 2]);
        assert_eq!(c.order(layout(240), 4), vec![0, 1, 2, 3], "times of another layout are not used");
        assert_eq!(c.order(layout(120), 5), vec![0, 1, 2, 3, 4], "nor times of another band count");
    }
}
