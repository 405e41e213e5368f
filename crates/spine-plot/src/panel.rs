//! A panel: axes with their labels and scales, and the series drawn on them.

use crate::series::Series;

/// How an axis maps and labels its values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// Linear, labels with the decimals the axis span needs (never "-0").
    #[default]
    Linear,
    /// Linear, counting things (nodes, links, joints): labels only at whole numbers.
    Integer,
    /// Base-10 logarithmic with decade labels `10^k` (quantities spanning decades: stiffness,
    /// damping); values ≤ 0 cannot be drawn and are left out.
    Log10,
}

/// Where a panel's legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LegendPlace {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
    /// Outside the axes, below the tick labels, entries side by side.
    Below,
}

/// One chart: a caption, axis labels with units, and its series.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Same scale on both axes (structure shapes).
    pub equal_aspect: bool,
    /// Fixed axis ranges; `None`: fitted to the data with a 5 % margin (a logarithmic axis from
    /// the decade below the smallest value; bars on a linear axis from 0).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// Where the legend goes; `None`: the first corner of the axes (upper right, upper left,
    /// lower right, lower left) that no point, line or bar reaches, else below the axes.
    pub legend: Option<LegendPlace>,
}

impl Panel {
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            equal_aspect: false,
            x_range: None,
            y_range: None,
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            legend: None,
        }
    }
    /// The x axis counts things: labels at whole numbers only.
    pub fn x_integer(mut self) -> Self {
        self.x_scale = Scale::Integer;
        self
    }
    /// A logarithmic x axis with decade labels.
    pub fn x_log(mut self) -> Self {
        self.x_scale = Scale::Log10;
        self
    }
    /// A logarithmic y axis with decade labels.
    pub fn y_log(mut self) -> Self {
        self.y_scale = Scale::Log10;
        self
    }
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
    pub fn equal_aspect(mut self) -> Self {
        self.equal_aspect = true;
        self
    }
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }
    /// Puts the legend at `place` whatever the data (frames of an animation keep it still).
    pub fn legend_at(mut self, place: LegendPlace) -> Self {
        self.legend = Some(place);
        self
    }
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
}
