//! Worker placement: one renderer worker to a core when the pool has as many workers as the process may use
//! cores.
//!
//! Why: a frame's fill starts when one worker wakes the other. Linux's scheduler puts a woken thread on the
//! core of the thread that woke it when it judges the two related, and a core that has just gone idle does
//! not always pull it back (its idle balancing is skipped after short idles and otherwise waits for a
//! tick). Measured in the game's window on a 2-core machine (`perf sched timehist`): the second worker
//! waited 4.4 ms behind the first on one core while the other core sat idle, and one frame in ten or so
//! took one thread's time. With each worker held to its own core that wait cannot happen.
//!
//! Only a pool that fills the process's cores is pinned: a smaller pool (a test among others, `--threads 2`
//! on a large machine) would put every process's workers on the same first cores, and a larger one would
//! stack two workers on a core for good. Elsewhere than Linux, and when the kernel refuses, nothing is
//! pinned and the scheduler places the workers as before.

/// The cores this process may run on, in order (empty when unknown or not on Linux).
#[must_use]
pub fn allowed_cores() -> Vec<usize> {
    #[cfg(target_os = "linux")]
    {
        use nix::sched::{CpuSet, sched_getaffinity};
        use nix::unistd::Pid;
        let Ok(set) = sched_getaffinity(Pid::from_raw(0)) else { return Vec::new() };
        (0..CpuSet::count()).filter(|&c| set.is_set(c).unwrap_or(false)).collect()
    }
    #[cfg(not(target_os = "linux"))]
    {
        Vec::new()
    }
}

/// The core worker `index` of a pool of `workers` is held to, when the pool is pinned: the `index`-th of
/// `cores` when there are exactly `workers` of them, else none.
#[must_use]
pub fn core_for(index: usize, workers: usize, cores: &[usize]) -> Option<usize> {
    (workers > 1 && cores.len() == workers).then(|| cores.get(index).copied()).flatten()
}

/// Holds the calling thread to `core`; false when the kernel refuses or the platform has no such call (the
/// thread then runs where the scheduler puts it, which is correct, only slower at times).
pub fn pin_current_thread(core: usize) -> bool {
    #[cfg(target_os = "linux")]
    {
        use nix::sched::{CpuSet, sched_setaffinity};
        use nix::unistd::Pid;
        let mut set = CpuSet::new();
        set.set(core).is_ok() && sched_setaffinity(Pid::from_raw(0), &set).is_ok()
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = core;
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pool_is_pinned_only_when_it_fills_the_allowed_cores() {
        let cores = [2, 5, 7];
        assert_eq!((0..3).map(|i| core_for(i, 3, &cores)).collect::<Vec<_>>(), [Some(2), Some(5), Some(7)]);
        // Fewer workers than cores: another pool would land on the same first cores.
        assert_eq!(core_for(0, 2, &cores), None);
        // More workers than cores: two would share a core for good.
        assert_eq!(core_for(0, 4, &cores), None);
        // One worker, or cores unknown.
        assert_eq!(core_for(0, 1, &[0]), None);
        assert_eq!(core_for(0, 2, &[]), None);
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_pinned_thread_runs_on_its_core_only() {
        let cores = allowed_cores();
        assert!(!cores.is_empty(), "Linux reports the cores a process may use");
        let last = *cores.last().expect("a core");
        let seen = std::thread::spawn(move || {
            assert!(pin_current_thread(last));
            allowed_cores()
        })
        .join()
        .expect("thread");
        assert_eq!(seen, [last]);
        // The pin is the thread's own: this thread keeps every core.
        assert_eq!(allowed_cores(), cores);
    }
}
