//! Keeps the process running when the X server goes away, so that a race being recorded is kept.
//!
//! Xlib's default answer to a broken connection is to print a line and call `exit(1)` from inside whatever
//! Xlib call noticed it: the window's loop never learns of it, and the race's trace is left in its
//! temporary file, unnamed. libX11 1.7 and later take, per display, an exit handler that may return
//! instead (`XSetIOErrorExitHandler`); Xlib then marks the display dead, winit's next request on it fails,
//! and the window ends with "the display connection failed" like any other display error, after the race
//! is kept. The silent I/O error handler keeps Xlib's line off the terminal (the window says what failed).
//! Both functions are looked up in the libX11 winit has already loaded; without them (an older libX11, or
//! a Wayland window) nothing changes.
//!
//! This is the shell's one foreign call, so its one `unsafe` block.

use std::ffi::{c_int, c_void};

use winit::raw_window_handle::{HasDisplayHandle, RawDisplayHandle};

/// Xlib's `XIOErrorHandler`.
type IoErrorHandler = extern "C" fn(*mut c_void) -> c_int;
/// Xlib's `XIOErrorExitHandler`.
type IoErrorExitHandler = extern "C" fn(*mut c_void, *mut c_void);
/// `XSetIOErrorHandler`.
type SetIoErrorHandler = unsafe extern "C" fn(Option<IoErrorHandler>) -> Option<IoErrorHandler>;
/// `XSetIOErrorExitHandler`.
type SetIoErrorExitHandler = unsafe extern "C" fn(*mut c_void, Option<IoErrorExitHandler>, *mut c_void);

/// The I/O error handler: says nothing (the window reports the error) and returns, as libX11 1.7 allows.
extern "C" fn quiet(_display: *mut c_void) -> c_int {
    0
}

/// The exit handler: returns instead of exiting, leaving the display dead for winit to notice.
extern "C" fn carry_on(_display: *mut c_void, _data: *mut c_void) {}

/// Installs the handlers for the Xlib display `window` is on; `false` when the window is not on Xlib or the
/// loaded libX11 has no exit handler (then Xlib keeps its default).
pub(crate) fn keep_running(window: &winit::window::Window) -> bool {
    let Ok(handle) = window.display_handle() else { return false };
    let RawDisplayHandle::Xlib(xlib) = handle.as_raw() else { return false };
    let Some(display) = xlib.display else { return false };
    // SAFETY: `dlopen` with RTLD_NOLOAD only finds a library already loaded (winit loaded libX11 to open this
    // window) and `dlsym` only looks names up; both take NUL-terminated names. The symbols, when found, are
    // libX11's `XSetIOErrorHandler` and `XSetIOErrorExitHandler`, whose C signatures the two function types
    // above repeat, so the transmutes give callable pointers of the right types. `display` is the live
    // `Display*` winit holds for the window (it outlives this call), and the handlers are `extern "C"`
    // functions that live for the whole program and touch nothing. `dlclose` drops only the reference this
    // `dlopen` took.
    #[allow(unsafe_code)]
    unsafe {
        let lib = libc::dlopen(c"libX11.so.6".as_ptr(), libc::RTLD_NOW | libc::RTLD_NOLOAD);
        if lib.is_null() {
            return false;
        }
        let set_io = libc::dlsym(lib, c"XSetIOErrorHandler".as_ptr());
        let set_exit = libc::dlsym(lib, c"XSetIOErrorExitHandler".as_ptr());
        let found = !set_io.is_null() && !set_exit.is_null();
        if found {
            let set_io: SetIoErrorHandler = std::mem::transmute::<*mut c_void, SetIoErrorHandler>(set_io);
            let set_exit: SetIoErrorExitHandler = std::mem::transmute::<*mut c_void, SetIoErrorExitHandler>(set_exit);
            set_io(Some(quiet));
            set_exit(display.as_ptr(), Some(carry_on), std::ptr::null_mut());
        }
        libc::dlclose(lib);
        found
    }
}
