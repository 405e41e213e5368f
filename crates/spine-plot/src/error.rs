//! Why a figure could not be drawn.

/// A drawing failure: a backend's (plotters', usvg's, the PDF and GIF writers', whose error types
/// are generic over the backend, so the cause travels as its message), or one of the workspace's
/// own, each with its numbers.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlotError {
    /// A backend's description of the failure.
    #[error("plot: {0}")]
    Backend(String),
    /// An animation without frames.
    #[error("plot: gif: no frames")]
    NoFrames,
    /// A frame wider or taller than a GIF can hold (65535 px).
    #[error("plot: gif: {width}×{height} px is larger than a GIF can hold (65535)")]
    FrameTooLarge { width: u32, height: u32 },
    /// A frame whose size differs from the first frame's.
    #[error("plot: gif: a frame of {frame_width}×{frame_height} px among frames of {width}×{height} px")]
    FrameSize { frame_width: u32, frame_height: u32, width: u32, height: u32 },
    /// An animation asked of a result with no response in it.
    #[error("plot: animation: no response to animate")]
    NothingToAnimate,
}

pub(crate) fn err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Backend(e.to_string())
}
