//! A single-producer, single-consumer ring of samples built from atomics only (no lock, no `unsafe`): the
//! game thread pushes, the audio callback pops, and neither ever waits for the other.
//!
//! Each slot holds an `f32`'s bits in an `AtomicU32`. The producer writes slots, then publishes them by a
//! release store of the write count; the consumer reads the slots below that count after an acquire load,
//! then frees them by a release store of the read count. A full ring drops what does not fit (the game is
//! ahead of the device); an empty one leaves the callback to play silence (the game is behind).

use std::sync::Arc;
use std::sync::atomic::{AtomicU32, AtomicU64, AtomicUsize, Ordering};

/// The shared ring.
#[derive(Debug)]
pub struct Ring {
    slots: Vec<AtomicU32>,
    /// Samples ever written (the producer's count).
    written: AtomicUsize,
    /// Samples ever read (the consumer's count).
    read: AtomicUsize,
    /// Samples the consumer wanted and did not find (played as silence).
    underruns: AtomicU64,
}

impl Ring {
    /// A ring of `capacity` samples (at least one).
    #[must_use]
    pub fn new(capacity: usize) -> Arc<Self> {
        Arc::new(Self {
            slots: (0..capacity.max(1)).map(|_| AtomicU32::new(0)).collect(),
            written: AtomicUsize::new(0),
            read: AtomicUsize::new(0),
            underruns: AtomicU64::new(0),
        })
    }

    /// Samples waiting to be played.
    #[must_use]
    pub fn len(&self) -> usize {
        self.written.load(Ordering::Acquire).wrapping_sub(self.read.load(Ordering::Acquire))
    }

    /// Whether nothing waits to be played.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Samples the consumer found missing so far.
    #[must_use]
    pub fn underruns(&self) -> u64 {
        self.underruns.load(Ordering::Relaxed)
    }

    /// Producer: appends as many of `samples` as fit and returns how many did; never blocks.
    pub fn push(&self, samples: &[f32]) -> usize {
        let w = self.written.load(Ordering::Relaxed);
        let r = self.read.load(Ordering::Acquire);
        let free = self.slots.len() - w.wrapping_sub(r);
        let n = samples.len().min(free);
        for (k, &x) in samples[..n].iter().enumerate() {
            self.slots[w.wrapping_add(k) % self.slots.len()].store(x.to_bits(), Ordering::Relaxed);
        }
        self.written.store(w.wrapping_add(n), Ordering::Release);
        n
    }

    /// Consumer: fills `out` with waiting samples and the rest with silence (counted as underruns); never
    /// blocks. Returns how many real samples it took.
    pub fn pop_into(&self, out: &mut [f32]) -> usize {
        let r = self.read.load(Ordering::Relaxed);
        let w = self.written.load(Ordering::Acquire);
        let n = out.len().min(w.wrapping_sub(r));
        for (k, o) in out[..n].iter_mut().enumerate() {
            *o = f32::from_bits(self.slots[r.wrapping_add(k) % self.slots.len()].load(Ordering::Relaxed));
        }
        out[n..].fill(0.0);
        self.read.store(r.wrapping_add(n), Ordering::Release);
        self.underruns.fetch_add((out.len() - n) as u64, Ordering::Relaxed);
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_order_across_the_wrap_and_never_overfills() {
        let ring = Ring::new(8);
        assert_eq!(ring.push(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]), 6);
        let mut out = [9.0; 4];
        assert_eq!(ring.pop_into(&mut out), 4);
        assert_eq!(out, [1.0, 2.0, 3.0, 4.0]);
        assert_eq!(ring.push(&[7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0]), 6, "two were waiting: six fit");
        let mut all = [0.0; 10];
        assert_eq!(ring.pop_into(&mut all), 8);
        assert_eq!(all, [5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 0.0, 0.0]);
        assert_eq!(ring.underruns(), 2);
        assert!(ring.is_empty());
    }

    #[test]
    fn a_consumer_thread_reads_what_the_producer_wrote_in_order() {
        let ring = Ring::new(64);
        let reader = Arc::clone(&ring);
        let total = 200_000usize;
        let handle = std::thread::spawn(move || {
            let (mut got, mut next, mut buf) = (0usize, 0.0f32, [0.0f32; 17]);
            while got < total {
                let n = reader.pop_into(&mut buf);
                for &x in &buf[..n] {
                    assert_eq!(x, next);
                    next = if next >= 1000.0 { 0.0 } else { next + 1.0 };
                }
                got += n;
            }
        });
        let (mut sent, mut v) = (0usize, 0.0f32);
        while sent < total {
            let chunk: Vec<f32> = (0..(total - sent).min(13)).map(|k| (v + k as f32) % 1001.0).collect();
            let n = ring.push(&chunk);
            sent += n;
            v = (v + n as f32) % 1001.0;
        }
        handle.join().expect("the consumer saw every sample in order");
    }
}
