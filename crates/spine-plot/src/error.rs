//! Why a figure could not be drawn.

/// A drawing failure, with plotters' description of it (its error types are generic over the
/// backend, so the cause travels as its message).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);

pub(crate) fn err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError(e.to_string())
}
