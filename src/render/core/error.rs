//! Why a frame could not be drawn.

use thiserror::Error;

/// Why a frame could not be drawn.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum RenderError {
    /// The pixel slice is shorter than `width * height`.
    #[error("frame buffer holds {len} pixels, but {width}x{height} needs {needed}")]
    FrameTooSmall {
        /// Pixels supplied.
        len: usize,
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
        /// `width * height` (saturated).
        needed: usize,
    },
    /// The frame is too large for the fixed-point grid (more than 2^20 pixels on a side).
    #[error("frame of {width}x{height} is larger than the renderer supports (2^20 on a side)")]
    FrameTooLarge {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// The fill stage's worker threads could not be started.
    #[error("could not start the fill worker threads")]
    WorkerFailed,
}
