//! A series of `(x, y)` points and how it is drawn.

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Line,
    /// A dashed line (reference curves: an undeformed shape, a fitted model, a target).
    Dashed,
    Markers,
    LineMarkers,
    /// Vertical bars from 0; several bar series in one panel stand side by side.
    Bars,
}

/// One named set of points.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Index into the colour cycle; `None`: the series' position in the panel.
    pub colour: Option<usize>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Self { label: label.into(), points, style, colour: None }
    }
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Line)
    }
    pub fn dashed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Dashed)
    }
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Markers)
    }
    pub fn line_markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::LineMarkers)
    }
    pub fn bars(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Bars)
    }
    /// Uses colour `k` of the cycle (to keep one colour per run across panels).
    pub fn colour(mut self, k: usize) -> Self {
        self.colour = Some(k);
        self
    }
}
