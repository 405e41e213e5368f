//! Where everything of a figure goes, in pixels: the title's lines, each panel's caption, axes box
//! and axis ranges, the marks the data makes, and the legend's box, placed in a corner no data
//! reaches or, when every corner is taken, below the axes. Drawing follows this layout, and the
//! figure's checks read it ([`Figure::layout`](crate::Figure::layout)).

use crate::axes::{in_axis_coordinates, ranges};
use crate::panel::{LegendPlace, Panel, Scale};
use crate::series::Style;
use crate::style::{CAPTION_SIZE, LEGEND_SIZE, MARGIN, TITLE_SIZE, X_LABEL_AREA, Y_LABEL_AREA};
use crate::text::{width, FittedText};

/// A rectangle in pixels, `y` downwards.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Self { x0, y0, x1, y1 }
    }
    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }
    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }
    /// The rectangles share interior points.
    pub fn intersects(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
    /// `o` lies within this rectangle, `tolerance` px allowed outside.
    pub fn holds(&self, o: &Rect, tolerance: f64) -> bool {
        o.x0 >= self.x0 - tolerance
            && o.y0 >= self.y0 - tolerance
            && o.x1 <= self.x1 + tolerance
            && o.y1 <= self.y1 + tolerance
    }
    /// Grown by `d` px on every side.
    pub fn grown(&self, d: f64) -> Self {
        Self::new(self.x0 - d, self.y0 - d, self.x1 + d, self.y1 + d)
    }
    /// The segment from `a` to `b` passes through the rectangle (Liang–Barsky clipping).
    pub fn hits_segment(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (p, q) in [(-dx, a.0 - self.x0), (dx, self.x1 - a.0), (-dy, a.1 - self.y0), (dy, self.y1 - a.1)] {
            if p == 0.0 {
                if q < 0.0 {
                    return false;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
                if t0 > t1 {
                    return false;
                }
            }
        }
        true
    }
}

/// What a series puts on the axes, in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mark {
    /// A piece of a line between two consecutive points.
    Segment((f64, f64), (f64, f64)),
    /// A marker or a bar.
    Box(Rect),
}

impl Mark {
    pub fn hits(&self, r: &Rect) -> bool {
        match self {
            Mark::Segment(a, b) => r.hits_segment(*a, *b),
            Mark::Box(b) => r.intersects(b),
        }
    }
}

/// One entry of a legend: the series, its swatch and where its label starts (left, middle).
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    pub series: usize,
    pub swatch: Rect,
    pub label_at: (f64, f64),
}

/// A panel's legend: where it went, its box and its entries.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendLayout {
    pub place: LegendPlace,
    pub rect: Rect,
    pub entries: Vec<LegendEntry>,
}

/// One panel laid out.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelLayout {
    /// The panel's cell of the figure's grid.
    pub cell: Rect,
    pub caption: FittedText,
    /// Top of the caption's first line.
    pub caption_top: f64,
    /// The axes box and the tick-label areas left of and below it (what plotters is given).
    pub chart: Rect,
    /// The axes box.
    pub plot: Rect,
    /// Axis ranges in axis coordinates (`log10` of the value on a logarithmic axis).
    pub x: (f64, f64),
    pub y: (f64, f64),
    /// Font sizes of the axis descriptions, shrunk to the axes' length when needed, px.
    pub x_label_size: f64,
    pub y_label_size: f64,
    /// `(series, mark)` for every drawn point, line piece and bar.
    pub marks: Vec<(usize, Mark)>,
    pub legend: Option<LegendLayout>,
}

impl PanelLayout {
    /// Pixel position of a point in axis coordinates.
    pub fn to_px(&self, (x, y): (f64, f64)) -> (f64, f64) {
        to_px(&self.plot, self.x, self.y, (x, y))
    }
}

/// A figure laid out: its size, title and panels.
#[derive(Clone, Debug, PartialEq)]
pub struct FigureLayout {
    pub size: (u32, u32),
    pub title: FittedText,
    /// Height of the title band, px.
    pub title_height: f64,
    pub panels: Vec<PanelLayout>,
}

const LEGEND_PAD: f64 = 6.0;
const LEGEND_ROW: f64 = 16.0;
const SWATCH: f64 = 20.0;
/// Space kept between a legend and the nearest mark or axis, px.
const LEGEND_CLEARANCE: f64 = 3.0;

fn to_px(plot: &Rect, x: (f64, f64), y: (f64, f64), p: (f64, f64)) -> (f64, f64) {
    (plot.x0 + (p.0 - x.0) / (x.1 - x.0) * plot.width(), plot.y1 - (p.1 - y.0) / (y.1 - y.0) * plot.height())
}

/// The axis-coordinate rectangle of bar `slot` of `count` bar series at `(x, y)`, from `base`.
pub(crate) fn bar(x: f64, y: f64, base: f64, slot: usize, count: usize) -> ((f64, f64), (f64, f64)) {
    let width = 0.8 / count.max(1) as f64;
    let left = x - 0.4 + slot as f64 * width;
    ((left, base), (left + width, y))
}

/// Where bars start: 0 on a linear axis, the bottom of a logarithmic one.
pub(crate) fn bar_base(scale: Scale, y: (f64, f64)) -> f64 {
    if scale == Scale::Log10 {
        y.0
    } else {
        0.0
    }
}

/// The marks of `panel` (in axis coordinates) on `plot` with ranges `x`, `y`.
fn marks(panel: &Panel, plot: &Rect, x: (f64, f64), y: (f64, f64)) -> Vec<(usize, Mark)> {
    let bars: Vec<usize> = (0..panel.series.len()).filter(|&k| panel.series[k].style == Style::Bars).collect();
    let base = bar_base(panel.y_scale, y);
    let px = |p| to_px(plot, x, y, p);
    let mut out = Vec::new();
    for (k, s) in panel.series.iter().enumerate() {
        let points: Vec<(f64, f64)> = s.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        if matches!(s.style, Style::Line | Style::Dashed | Style::LineMarkers) {
            out.extend(points.windows(2).map(|w| (k, Mark::Segment(px(w[0]), px(w[1])))));
        }
        if matches!(s.style, Style::Markers | Style::LineMarkers) {
            out.extend(points.iter().map(|&p| {
                let (cx, cy) = px(p);
                (k, Mark::Box(Rect::new(cx - 3.0, cy - 3.0, cx + 3.0, cy + 3.0)))
            }));
        }
        if s.style == Style::Bars {
            let slot = bars.iter().position(|&i| i == k).unwrap_or(0);
            out.extend(points.iter().map(|&(bx, by)| {
                let (a, b) = bar(bx, by, base, slot, bars.len());
                let (a, b) = (px(a), px(b));
                (k, Mark::Box(Rect::new(a.0.min(b.0), a.1.min(b.1), a.0.max(b.0), a.1.max(b.1))))
            }));
        }
    }
    out
}

/// The legend's entries stacked in one column, top left at `(0, 0)`: its size and entries.
fn column(panel: &Panel, labelled: &[usize]) -> ((f64, f64), Vec<LegendEntry>) {
    let text = labelled.iter().map(|&k| width(&panel.series[k].label, LEGEND_SIZE)).fold(0.0, f64::max);
    let entries = labelled
        .iter()
        .enumerate()
        .map(|(row, &series)| {
            let mid = LEGEND_PAD + (row as f64 + 0.5) * LEGEND_ROW;
            LegendEntry {
                series,
                swatch: Rect::new(LEGEND_PAD, mid - 5.0, LEGEND_PAD + SWATCH, mid + 5.0),
                label_at: (LEGEND_PAD + SWATCH + 6.0, mid),
            }
        })
        .collect();
    ((2.0 * LEGEND_PAD + SWATCH + 6.0 + text.ceil(), 2.0 * LEGEND_PAD + LEGEND_ROW * labelled.len() as f64), entries)
}

/// The legend's entries in rows as wide as `max_width`, top left at `(0, 0)`.
fn rows(panel: &Panel, labelled: &[usize], max_width: f64) -> ((f64, f64), Vec<LegendEntry>) {
    let mut entries = Vec::new();
    let (mut x, mut row, mut widest) = (LEGEND_PAD, 0usize, 0.0_f64);
    for &series in labelled {
        let w = SWATCH + 6.0 + width(&panel.series[series].label, LEGEND_SIZE).ceil();
        if x > LEGEND_PAD && x + w + LEGEND_PAD > max_width {
            (x, row) = (LEGEND_PAD, row + 1);
        }
        let mid = LEGEND_PAD + (row as f64 + 0.5) * LEGEND_ROW;
        entries.push(LegendEntry {
            series,
            swatch: Rect::new(x, mid - 5.0, x + SWATCH, mid + 5.0),
            label_at: (x + SWATCH + 6.0, mid),
        });
        widest = widest.max(x + w + LEGEND_PAD);
        x += w + 16.0;
    }
    ((widest, 2.0 * LEGEND_PAD + LEGEND_ROW * (row + 1) as f64), entries)
}

fn shifted(entries: Vec<LegendEntry>, dx: f64, dy: f64) -> Vec<LegendEntry> {
    entries
        .into_iter()
        .map(|e| LegendEntry {
            series: e.series,
            swatch: Rect::new(e.swatch.x0 + dx, e.swatch.y0 + dy, e.swatch.x1 + dx, e.swatch.y1 + dy),
            label_at: (e.label_at.0 + dx, e.label_at.1 + dy),
        })
        .collect()
}

/// The axes box inside `chart`, narrowed or shortened (top-aligned, centred across) so that a
/// metre is as long on both axes when `equal` is set.
fn axes_box(chart: &Rect, x: (f64, f64), y: (f64, f64), equal: bool) -> (Rect, Rect) {
    let plot = Rect::new(chart.x0 + f64::from(Y_LABEL_AREA), chart.y0, chart.x1, chart.y1 - f64::from(X_LABEL_AREA));
    if !equal {
        return (*chart, plot);
    }
    let (sx, sy) = ((x.1 - x.0) / plot.width(), (y.1 - y.0) / plot.height());
    let (mut chart, mut plot) = (*chart, plot);
    if sx > sy {
        let h = ((y.1 - y.0) / sx).round();
        chart.y1 -= plot.height() - h;
        plot.y1 = plot.y0 + h;
    } else {
        let w = ((x.1 - x.0) / sy).round();
        let inset = ((plot.width() - w) / 2.0).floor();
        chart.x0 += inset;
        plot.x0 += inset;
        chart.x1 = plot.x0 + w;
        plot.x1 = chart.x1;
    }
    (chart, plot)
}

fn lay_out_panel(panel: &Panel, cell: Rect, caption: FittedText, caption_band: f64) -> PanelLayout {
    let axis = in_axis_coordinates(panel);
    let (x, y) = ranges(&axis);
    let full = Rect::new(
        cell.x0 + f64::from(MARGIN),
        cell.y0 + caption_band,
        cell.x1 - f64::from(MARGIN),
        cell.y1 - f64::from(MARGIN),
    );
    let (mut chart, mut plot) = axes_box(&full, x, y, panel.equal_aspect);
    let labelled: Vec<usize> = (0..panel.series.len()).filter(|&k| !panel.series[k].label.is_empty()).collect();
    let mut drawn = marks(&axis, &plot, x, y);
    let mut legend = None;
    if !labelled.is_empty() {
        let ((w, h), entries) = column(&axis, &labelled);
        let inner = plot.grown(-8.0);
        let corner = |place: LegendPlace| match place {
            LegendPlace::UpperRight => Some(Rect::new(inner.x1 - w, inner.y0, inner.x1, inner.y0 + h)),
            LegendPlace::UpperLeft => Some(Rect::new(inner.x0, inner.y0, inner.x0 + w, inner.y0 + h)),
            LegendPlace::LowerRight => Some(Rect::new(inner.x1 - w, inner.y1 - h, inner.x1, inner.y1)),
            LegendPlace::LowerLeft => Some(Rect::new(inner.x0, inner.y1 - h, inner.x0 + w, inner.y1)),
            LegendPlace::Below => None,
        };
        let free = |r: &Rect| inner.holds(r, 0.0) && !drawn.iter().any(|(_, m)| m.hits(&r.grown(LEGEND_CLEARANCE)));
        let places = match panel.legend {
            Some(place) => vec![place],
            None => {
                vec![LegendPlace::UpperRight, LegendPlace::UpperLeft, LegendPlace::LowerRight, LegendPlace::LowerLeft]
            }
        };
        let inside =
            places.iter().find_map(|&p| corner(p).filter(|r| panel.legend.is_some() || free(r)).map(|r| (p, r)));
        legend = Some(match inside {
            Some((place, rect)) => LegendLayout { place, rect, entries: shifted(entries, rect.x0, rect.y0) },
            None => {
                let ((w, h), entries) = rows(&axis, &labelled, full.width());
                let room = full.y1 - chart.y1;
                if room < h + 4.0 {
                    let shorter = Rect::new(full.x0, full.y0, full.x1, full.y1 - (h + 4.0));
                    (chart, plot) = axes_box(&shorter, x, y, panel.equal_aspect);
                    drawn = marks(&axis, &plot, x, y);
                }
                let left = (0.5 * (plot.x0 + plot.x1 - w)).min(full.x1 - w).max(full.x0).round();
                let top = chart.y1 + 4.0;
                LegendLayout {
                    place: LegendPlace::Below,
                    rect: Rect::new(left, top, left + w, top + h),
                    entries: shifted(entries, left, top),
                }
            }
        });
    }
    let fit = |text: &str, length: f64| FittedText::fit(text, crate::style::AXIS_LABEL_SIZE, 9.0, 1, length).size;
    PanelLayout {
        cell,
        caption,
        caption_top: cell.y0 + f64::from(MARGIN),
        chart,
        plot,
        x,
        y,
        x_label_size: fit(&panel.x_label, plot.width()),
        y_label_size: fit(&panel.y_label, plot.height()),
        marks: drawn,
        legend,
    }
}

/// Lays out `panels` in `columns` columns of cells of `panel_size` px under `title`.
pub(crate) fn lay_out(title: &str, columns: usize, panels: &[Panel], panel_size: (u32, u32)) -> FigureLayout {
    let columns = columns.min(panels.len().max(1)).max(1);
    let rows = panels.len().div_ceil(columns).max(1);
    let (pw, ph) = (f64::from(panel_size.0), f64::from(panel_size.1));
    let width = pw * columns as f64;
    let title = FittedText::fit(title, TITLE_SIZE, 13.0, 2, width - 2.0 * f64::from(MARGIN));
    let title_height = (10.0 + title.height() + 4.0).ceil();
    let captions: Vec<FittedText> =
        panels.iter().map(|p| FittedText::fit(&p.title, CAPTION_SIZE, 11.0, 2, pw - 2.0 * f64::from(MARGIN))).collect();
    let caption_band = f64::from(MARGIN) + captions.iter().map(FittedText::height).fold(0.0, f64::max) + 6.0;
    let laid: Vec<PanelLayout> = panels
        .iter()
        .zip(captions)
        .enumerate()
        .map(|(k, (panel, caption))| {
            let (row, col) = ((k / columns) as f64, (k % columns) as f64);
            let cell = Rect::new(col * pw, title_height + row * ph, (col + 1.0) * pw, title_height + (row + 1.0) * ph);
            lay_out_panel(panel, cell, caption, caption_band)
        })
        .collect();
    FigureLayout { size: (width as u32, (title_height + ph * rows as f64) as u32), title, title_height, panels: laid }
}
