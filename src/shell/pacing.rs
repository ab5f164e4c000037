//! How the window times its frames: one per refresh of the display (the rate winit reports, a rate the
//! player chose with `--fps`, or [`FALLBACK_HZ`]), or as many as the CPU allows (`--uncapped`).
//!
//! The loop sleeps until the next frame is due; a late frame does not make the next ones hurry
//! ([`Pacing::next_due`]). `auto` quality takes its budget from the same period.

use std::time::{Duration, Instant};

/// The refresh rate assumed when the display reports none.
pub const FALLBACK_HZ: f64 = 60.0;

/// The rates `--fps` and a display may give, in frames a second; others are not taken.
pub const RATES: std::ops::RangeInclusive<f64> = 20.0..=1000.0;

/// Where the paced rate came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RateSource {
    /// The display reported it.
    Display,
    /// The display reported none (or one outside [`RATES`]): [`FALLBACK_HZ`].
    Fallback,
    /// The player chose it (`--fps`).
    Chosen,
}

/// How the window times its frames; F3 shows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pacing {
    /// One frame per refresh, at `hz`.
    Paced {
        /// Frames a second.
        hz: f64,
        /// Where the rate came from.
        source: RateSource,
    },
    /// As many frames as the CPU allows (`play --uncapped`), for measuring.
    Uncapped,
}

impl Pacing {
    /// The pacing for a display reporting `millihertz` (if anything) and the player's `fps` (if chosen),
    /// or uncapped unless `paced`. A rate outside [`RATES`] is not taken.
    #[must_use]
    pub fn new(paced: bool, fps: Option<f64>, millihertz: Option<u32>) -> Self {
        let chosen = fps.filter(|hz| RATES.contains(hz));
        let reported = millihertz.map(|m| f64::from(m) / 1000.0).filter(|hz| RATES.contains(hz));
        match (paced, chosen, reported) {
            (false, _, _) => Pacing::Uncapped,
            (true, Some(hz), _) => Pacing::Paced { hz, source: RateSource::Chosen },
            (true, None, Some(hz)) => Pacing::Paced { hz, source: RateSource::Display },
            (true, None, None) => Pacing::Paced { hz: FALLBACK_HZ, source: RateSource::Fallback },
        }
    }

    /// The time between frames, or `None` when uncapped.
    #[must_use]
    pub fn period(self) -> Option<Duration> {
        match self {
            Pacing::Paced { hz, .. } => Some(Duration::from_secs_f64(1.0 / hz)),
            Pacing::Uncapped => None,
        }
    }

    /// The frame period `auto` quality budgets against, in ms: the paced period, or the display's (or
    /// [`FALLBACK_HZ`]'s) when uncapped, since a frame no display shows is no reason to draw worse.
    #[must_use]
    pub fn budget_period_ms(self) -> f64 {
        match self {
            Pacing::Paced { hz, .. } => 1000.0 / hz,
            Pacing::Uncapped => 1000.0 / FALLBACK_HZ,
        }
    }

    /// When the frame after one due at `due` is due, the frame having started at `now`: one period on, or
    /// one period from `now` when the frame started more than a period late (a late frame does not make
    /// the next ones hurry to catch up).
    #[must_use]
    pub fn next_due(period: Duration, due: Instant, now: Instant) -> Instant {
        if now.saturating_duration_since(due) > period { now + period } else { due + period }
    }
}

impl std::fmt::Display for Pacing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Pacing::Paced { hz, source: RateSource::Display } => write!(f, "paced to {hz:.0} Hz (the display's rate)"),
            Pacing::Paced { hz, source: RateSource::Fallback } => {
                write!(f, "paced to {hz:.0} Hz (the display reports no rate)")
            }
            Pacing::Paced { hz, source: RateSource::Chosen } => write!(f, "paced to {hz:.0} Hz (--fps)"),
            Pacing::Uncapped => f.write_str("uncapped (--uncapped)"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pacing_takes_the_chosen_rate_else_the_display_s_within_reason_else_60_hz() {
        let paced = |hz, source| Pacing::Paced { hz, source };
        assert_eq!(Pacing::new(true, None, Some(144_000)), paced(144.0, RateSource::Display));
        assert_eq!(Pacing::new(true, None, Some(59_940)), paced(59.94, RateSource::Display));
        for odd in [None, Some(0), Some(5_000), Some(u32::MAX)] {
            assert_eq!(Pacing::new(true, None, odd), paced(FALLBACK_HZ, RateSource::Fallback), "{odd:?}");
        }
        assert_eq!(Pacing::new(true, Some(30.0), Some(144_000)), paced(30.0, RateSource::Chosen));
        assert_eq!(Pacing::new(true, Some(f64::NAN), None), paced(FALLBACK_HZ, RateSource::Fallback));
        assert_eq!(Pacing::new(false, Some(30.0), Some(60_000)), Pacing::Uncapped);
        assert_eq!(Pacing::Uncapped.period(), None);
        assert_eq!(Pacing::new(true, None, Some(50_000)).period(), Some(Duration::from_millis(20)));
        assert_eq!(Pacing::new(true, None, None).to_string(), "paced to 60 Hz (the display reports no rate)");
        assert_eq!(Pacing::new(true, Some(30.0), None).to_string(), "paced to 30 Hz (--fps)");
        assert!((Pacing::new(true, Some(30.0), None).budget_period_ms() - 33.333).abs() < 1e-3);
        assert!((Pacing::Uncapped.budget_period_ms() - 16.667).abs() < 1e-3);
    }

    #[test]
    fn a_frame_is_due_a_period_after_the_last_unless_it_started_more_than_a_period_late() {
        let (t0, p) = (Instant::now(), Duration::from_millis(16));
        // On time or a little late: the schedule keeps its beat.
        assert_eq!(Pacing::next_due(p, t0, t0), t0 + p);
        assert_eq!(Pacing::next_due(p, t0, t0 + Duration::from_millis(5)), t0 + p);
        // More than a period late: the next frame is a period from now, not at once.
        let late = t0 + Duration::from_millis(40);
        assert_eq!(Pacing::next_due(p, t0, late), late + p);
    }
}
