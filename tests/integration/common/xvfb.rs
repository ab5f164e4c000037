//! An Xvfb server for the window tests, and xdotool to type into the window.
//!
//! One display is up at a time in this test binary (see [`Xvfb`]): each windowed game is a debug build
//! drawing on its own Xvfb, and several at once on a loaded two-core CI machine made the games' time bounds
//! measure the machine.

use std::os::unix::net::UnixStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

/// An Xvfb server on a free display, killed when dropped. It holds [`ONE_DISPLAY`] while it lives, so the
/// windowed tests of every module run one at a time (the other tests still run beside them).
pub struct Xvfb {
    child: Child,
    /// The display, as `:N`.
    pub display: String,
    _one: MutexGuard<'static, ()>,
}

/// Held by each [`Xvfb`] (a test that failed while holding it does not stop the others).
static ONE_DISPLAY: Mutex<()> = Mutex::new(());

static NEXT: AtomicUsize = AtomicUsize::new(0);

/// Set (by `scripts/test`, hence CI) to make a missing Xvfb a failure instead of a plainly reported skip.
pub const REQUIRE: &str = "SCANLINE_RACER_REQUIRE_XVFB";

impl Xvfb {
    /// Starts Xvfb; `None` (after saying so plainly) when it is not installed and not required.
    pub fn start() -> Option<Xvfb> {
        let one = ONE_DISPLAY.lock().unwrap_or_else(PoisonError::into_inner);
        for _ in 0..50 {
            // Other processes may run Xvfb too: each server takes its own display number. The audio test's
            // own Xvfb, started in this process outside the lock, takes numbers from 300 to 899, so these
            // start above, so the two never race for one number.
            let num = 1000 + (std::process::id() as usize * 7 + NEXT.fetch_add(1, Ordering::SeqCst)) % 800;
            let lock = format!("/tmp/.X{num}-lock");
            if Path::new(&lock).exists() {
                // A server killed without its cleanup (the stop tests kill some on purpose) leaves its lock:
                // one whose process is gone is removed with its socket, and the number is taken.
                if !stale_lock(&lock) {
                    continue;
                }
                let _ = std::fs::remove_file(&lock);
                let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{num}"));
            }
            // `-noreset`: by default the server resets when its last client leaves, refusing connections
            // meanwhile; the probe below and every xdotool call are such clients, so a game starting just
            // then could not connect ("Failed to open connection to X server", seen in two runs).
            let child = Command::new("Xvfb")
                .args([format!(":{num}").as_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp", "-noreset"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn();
            let mut child = match child {
                Ok(c) => c,
                Err(e) if std::env::var_os(REQUIRE).is_some() => {
                    panic!("cannot start Xvfb ({e}) and {REQUIRE} is set: install it (apt-get install xvfb)")
                }
                Err(e) => {
                    eprintln!(
                        "NOT RUN: this window test needs Xvfb, which cannot be started here ({e}); scripts/test installs it"
                    );
                    return None;
                }
            };
            let socket = format!("/tmp/.X11-unix/X{num}");
            let t = Instant::now();
            while t.elapsed() < Duration::from_secs(10) {
                if let Ok(Some(_)) = child.try_wait() {
                    break; // this display was taken after all: try another
                }
                // A socket left by a killed server refuses connections: wait until one is accepted, then make
                // sure the server is ours (another one on this display would make ours exit).
                if UnixStream::connect(&socket).is_ok() {
                    std::thread::sleep(Duration::from_millis(100));
                    if let Ok(None) = child.try_wait() {
                        return Some(Xvfb { child, display: format!(":{num}"), _one: one });
                    }
                    break;
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        panic!("no Xvfb display came up");
    }
}

/// Whether the X lock file `path` names a process that is gone (`/proc/PID` missing).
fn stale_lock(path: &str) -> bool {
    std::fs::read_to_string(path)
        .ok()
        .and_then(|t| t.trim().parse::<u32>().ok())
        .is_some_and(|pid| !Path::new(&format!("/proc/{pid}")).exists())
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Runs `xdotool` with `args` on `display`; false when it is not installed (and not required).
pub fn xdotool(display: &str, args: &[&str]) -> Option<String> {
    match Command::new("xdotool").args(args).env("DISPLAY", display).output() {
        Ok(o) if o.status.success() => Some(String::from_utf8_lossy(&o.stdout).trim().to_string()),
        Ok(o) => panic!("xdotool {args:?}: {}", String::from_utf8_lossy(&o.stderr)),
        Err(e) if std::env::var_os(REQUIRE).is_some() => panic!("cannot run xdotool ({e}) and {REQUIRE} is set"),
        Err(e) => {
            eprintln!("NOT RUN: this window test needs xdotool ({e}); scripts/test installs it");
            None
        }
    }
}
