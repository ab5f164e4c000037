//! Polite stops: while a [`StopSignals`] lives (the window's run and the keeping of its recording after
//! it), SIGTERM, SIGHUP and SIGINT end the window as the Quit menu does, so the race recorded so far is
//! kept and the exit status says which signal stopped it.
//!
//! Why: the default action of these signals ends the process at once, and a recording then stayed in its
//! hidden temporary file with nothing said (a `kill`, a shutdown, a closed terminal, Ctrl+C in the
//! terminal that started the game). A signal handler may only set a flag, so the handlers here store the
//! signal's number, and the event loop looks at it every turn. Repeats of SIGTERM and SIGHUP are ignored
//! until the recording is kept (a closing terminal sends SIGHUP twice within microseconds, once from the
//! shell and once from the kernel); a second SIGINT (Ctrl+C pressed again) takes the default action, so a
//! stuck shutdown can still be stopped from the keyboard. Once the [`StopSignals`] is dropped every signal
//! takes its default action again. A signal the process was started with ignored (`nohup` ignores
//! SIGHUP) is left ignored.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use signal_hook::consts::signal::{SIGHUP, SIGINT, SIGTERM};

/// A signal that asks the program to stop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopSignal {
    /// SIGHUP: the terminal closed.
    Hangup,
    /// SIGINT: Ctrl+C in the terminal.
    Interrupt,
    /// SIGTERM: `kill`, a shutdown, a service manager.
    Terminate,
}

impl StopSignal {
    /// The signal's number.
    #[must_use]
    pub fn number(self) -> i32 {
        match self {
            StopSignal::Hangup => SIGHUP,
            StopSignal::Interrupt => SIGINT,
            StopSignal::Terminate => SIGTERM,
        }
    }

    /// The exit status of a program stopped by the signal, by the shell's convention (128 + its number).
    #[must_use]
    pub fn exit_status(self) -> u8 {
        // Numbers 1, 2 and 15: the sum fits in a byte.
        u8::try_from(128 + self.number()).unwrap_or(u8::MAX)
    }

    fn from_number(n: usize) -> Option<Self> {
        [StopSignal::Hangup, StopSignal::Interrupt, StopSignal::Terminate]
            .into_iter()
            .find(|s| usize::try_from(s.number()).is_ok_and(|k| k == n))
    }
}

impl std::fmt::Display for StopSignal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            StopSignal::Hangup => "SIGHUP",
            StopSignal::Interrupt => "SIGINT",
            StopSignal::Terminate => "SIGTERM",
        })
    }
}

/// The stop signals caught while this lives; when dropped, they take their default action again.
pub struct StopSignals {
    /// The number of the first stop signal received (0: none yet).
    got: Arc<AtomicUsize>,
    /// Set on drop: every signal then takes its default action.
    armed: Arc<AtomicBool>,
}

impl StopSignals {
    /// Catches SIGTERM, SIGHUP and SIGINT (each that is not ignored already); `None` when a handler cannot
    /// be installed (the signals then keep their default action, as before).
    #[must_use]
    pub fn catch() -> Option<Self> {
        let got = Arc::new(AtomicUsize::new(0));
        let armed = Arc::new(AtomicBool::new(false));
        // Set by the first SIGINT (only its handlers hold it): a second one takes its default action.
        let interrupted = Arc::new(AtomicBool::new(false));
        let ignored = ignored_at_start();
        for sig in [SIGTERM, SIGHUP, SIGINT].into_iter().filter(|s| !ignored.contains(s)) {
            // Order matters: the default action is checked before this signal's own flags are set.
            signal_hook::flag::register_conditional_default(sig, Arc::clone(&armed)).ok()?;
            if sig == SIGINT {
                signal_hook::flag::register_conditional_default(sig, Arc::clone(&interrupted)).ok()?;
                signal_hook::flag::register(sig, Arc::clone(&interrupted)).ok()?;
            }
            // The stop is said as the last of these signals received.
            signal_hook::flag::register_usize(sig, Arc::clone(&got), usize::try_from(sig).ok()?).ok()?;
        }
        Some(Self { got, armed })
    }

    /// The stop signal received, if any.
    #[must_use]
    pub fn received(&self) -> Option<StopSignal> {
        StopSignal::from_number(self.got.load(Ordering::SeqCst))
    }
}

/// The stop signals this process was started with set to be ignored, read from Linux's
/// `/proc/self/status` (`SigIgn`, a hexadecimal mask, bit `n - 1` for signal `n`); none elsewhere.
fn ignored_at_start() -> Vec<i32> {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let mask = status
        .lines()
        .find_map(|l| l.strip_prefix("SigIgn:"))
        .and_then(|hex| u64::from_str_radix(hex.trim(), 16).ok())
        .unwrap_or(0);
    [SIGTERM, SIGHUP, SIGINT].into_iter().filter(|&s| (1..=64).contains(&s) && mask >> (s - 1) & 1 == 1).collect()
}

impl Drop for StopSignals {
    /// The signals' default action comes back (signal-hook cannot remove its handler: removing its
    /// actions would leave the signals ignored).
    fn drop(&mut self) {
        self.armed.store(true, Ordering::SeqCst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_signal_is_named_and_gives_the_shell_s_status() {
        assert_eq!(
            [StopSignal::Hangup, StopSignal::Interrupt, StopSignal::Terminate].map(StopSignal::exit_status),
            [129, 130, 143]
        );
        assert_eq!(StopSignal::from_number(15), Some(StopSignal::Terminate));
        assert_eq!(StopSignal::from_number(0), None);
        assert_eq!(StopSignal::Hangup.to_string(), "SIGHUP");
    }
}
