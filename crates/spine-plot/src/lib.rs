//! # spine-plot: figures as data, drawn to SVG
//!
//! A [`Figure`] is a grid of [`Panel`]s; a panel holds [`Series`] of `(x, y)` points drawn as
//! lines, markers or bars, with axis labels that carry their units. The figure is plain data, so a
//! figure recipe builds it from results and this crate only draws it ([`Figure::to_svg`]), with
//! [plotters](https://docs.rs/plotters). DejaVu Sans is embedded for text layout (its licence is
//! beside it in `assets/`), so no system font library is needed. The same figure always gives the
//! same bytes. [`Figure::to_pdf`] converts the SVG to a vector PDF sized for a journal page
//! (svg2pdf, the same embedded font).
//!
//! ```
//! use spine_plot::{Figure, Panel, Series};
//! let panel = Panel::new("(a) a line", "x (m)", "y (m)")
//!     .with(Series::line("y = x²", (0..=10).map(|i| (i as f64, (i * i) as f64)).collect()));
//! let svg = Figure::new("example", 1).with(panel).to_svg().unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```
#![forbid(unsafe_code)]

mod gif;

pub use gif::to_gif;

use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Tableau 10, the colours of successive series.
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is a valid TrueType file; a failure here would only lose text.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

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

/// One chart: a caption, axis labels with units, and its series.
#[derive(Clone, Debug, PartialEq)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Same scale on both axes (structure shapes).
    pub equal_aspect: bool,
    /// Fixed axis ranges; `None`: fitted to the data with a 5 % margin.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub x_scale: Scale,
    pub y_scale: Scale,
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
    pub fn y_range(mut self, lo: f64, hi: f64) -> Self {
        self.y_range = Some((lo, hi));
        self
    }
}

/// A grid of panels, filled row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    pub title: String,
    pub columns: usize,
    pub panels: Vec<Panel>,
    /// Size of one panel, px.
    pub panel_size: (u32, u32),
}

/// A drawing failure, with plotters' description of it (its error types are generic over the
/// backend, so the cause travels as its message).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);

fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

const TITLE_HEIGHT: u32 = 36;
const X_LABEL_AREA: u32 = 48;
const Y_LABEL_AREA: u32 = 78;
const MARGIN: u32 = 12;
const CAPTION: u32 = 28;

impl Figure {
    pub fn new(title: impl Into<String>, columns: usize) -> Self {
        Self { title: title.into(), columns: columns.max(1), panels: Vec::new(), panel_size: (560, 400) }
    }
    pub fn with(mut self, panel: Panel) -> Self {
        self.panels.push(panel);
        self
    }

    fn grid(&self) -> (usize, usize, (u32, u32)) {
        let columns = self.columns.min(self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(columns).max(1);
        (rows, columns, (self.panel_size.0 * columns as u32, self.panel_size.1 * rows as u32 + TITLE_HEIGHT))
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
        rows: usize,
        columns: usize,
    ) -> Result<(), PlotError> {
        register_font();
        root.fill(&WHITE).map_err(err)?;
        let (head, body) = root.split_vertically(TITLE_HEIGHT);
        head.draw_text(&self.title, &(FAMILY, 18).into_text_style(&head), (MARGIN as i32, 10)).map_err(err)?;
        let areas = body.split_evenly((rows, columns));
        for (area, panel) in areas.iter().zip(&self.panels) {
            draw_panel(area, panel, self.panel_size)?;
        }
        root.present().map_err(err)
    }

    /// Draws the figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        let (rows, columns, size) = self.grid();
        let mut text = String::new();
        self.draw(SVGBackend::with_string(&mut text, size).into_drawing_area(), rows, columns)?;
        Ok(text)
    }

    /// The figure as a vector PDF (svg2pdf, text set in the embedded font), scaled to a journal's
    /// width: one column (3.5 in) for a single panel, the full text width (7 in) for several.
    pub fn to_pdf(&self) -> Result<Vec<u8>, PlotError> {
        use svg2pdf::usvg;
        let svg = self.to_svg()?;
        let mut options = usvg::Options::default();
        let db = options.fontdb_mut();
        db.load_font_data(FONT.to_vec());
        // The SVG asks for the generic family plotters was given; it is the embedded font.
        let family = db.faces().next().and_then(|face| face.families.first()).map(|(name, _)| name.clone());
        if let Some(name) = family {
            db.set_sans_serif_family(name);
        }
        let tree = usvg::Tree::from_str(&svg, &options).map_err(err)?;
        let (_, columns, (width_px, _)) = self.grid();
        let width_in = if columns == 1 { 3.5 } else { 7.0 };
        let page = svg2pdf::PageOptions { dpi: width_px as f32 / width_in };
        svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), page).map(canonical_pdf).map_err(err)
    }

    /// The figure's size in pixels, `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        self.grid().2
    }

    /// Draws the figure into an RGB buffer (3 bytes per pixel, row by row), text rasterised with
    /// the embedded font; returns its width, height and pixels.
    pub fn to_rgb(&self) -> Result<(u32, u32, Vec<u8>), PlotError> {
        let (rows, columns, size) = self.grid();
        let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
        self.draw(BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area(), rows, columns)?;
        Ok((size.0, size.1, pixels))
    }

    /// Draws the figure as a PNG file at `path` (text rasterised with the embedded font).
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), PlotError> {
        let (rows, columns, size) = self.grid();
        self.draw(BitMapBackend::new(path, size).into_drawing_area(), rows, columns)
    }
}

fn finite_range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.filter(|v| v.is_finite()).fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

fn padded((lo, hi): (f64, f64)) -> (f64, f64) {
    let span = hi - lo;
    let pad = if span > 0.0 { 0.05 * span } else { 0.05 * lo.abs().max(1e-3) };
    (lo - pad, hi + pad)
}

/// Data ranges of a panel (bars include 0 and their half widths).
fn ranges(panel: &Panel, plot_px: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let has_bars = panel.series.iter().any(|s| s.style == Style::Bars);
    let xs = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = panel.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).chain(has_bars.then_some(0.0));
    let mut x = finite_range(xs).unwrap_or((0.0, 1.0));
    if has_bars {
        x = (x.0 - 0.5, x.1 + 0.5);
    }
    let mut x = panel.x_range.unwrap_or_else(|| if has_bars { x } else { padded(x) });
    let mut y = panel.y_range.unwrap_or_else(|| padded(finite_range(ys).unwrap_or((0.0, 1.0))));
    if panel.equal_aspect {
        // Widen the axis whose metres per pixel are fewer, about its centre.
        let (sx, sy) = ((x.1 - x.0) / plot_px.0, (y.1 - y.0) / plot_px.1);
        if sx > sy {
            let c = 0.5 * (y.0 + y.1);
            let half = 0.5 * sx * plot_px.1;
            y = (c - half, c + half);
        } else {
            let c = 0.5 * (x.0 + x.1);
            let half = 0.5 * sy * plot_px.0;
            x = (c - half, c + half);
        }
    }
    (x, y)
}

/// svg2pdf writes the entries of a resource dictionary (`/xo17 42 0 R` lines) in hash order, so
/// the same figure gives different bytes. Sorting each run of such lines puts them in one order;
/// a run keeps its length, so every object stays at its offset and the cross-reference table
/// stays valid. Streams are copied untouched.
fn canonical_pdf(pdf: Vec<u8>) -> Vec<u8> {
    fn is_entry(line: &[u8]) -> bool {
        let text = match std::str::from_utf8(line) {
            Ok(t) => t,
            Err(_) => return false,
        };
        let mut words = text.split_whitespace();
        text.starts_with(' ')
            && words.next().is_some_and(|w| w.starts_with('/'))
            && words.next().is_some_and(|w| w.bytes().all(|b| b.is_ascii_digit()))
            && words.next() == Some("0")
            && words.next() == Some("R")
            && words.next().is_none()
    }
    let mut out = Vec::with_capacity(pdf.len());
    let mut rest = &pdf[..];
    let mut run: Vec<&[u8]> = Vec::new();
    let flush = |run: &mut Vec<&[u8]>, out: &mut Vec<u8>| {
        run.sort();
        for line in run.drain(..) {
            out.extend_from_slice(line);
            out.push(b'\n');
        }
    };
    while !rest.is_empty() {
        let end = rest.iter().position(|&b| b == b'\n').map_or(rest.len(), |i| i + 1);
        let (line, tail) = rest.split_at(end);
        let body = line.strip_suffix(b"\n").unwrap_or(line);
        if line.ends_with(b"\n") && is_entry(body) {
            run.push(body);
            rest = tail;
            continue;
        }
        flush(&mut run, &mut out);
        out.extend_from_slice(line);
        rest = tail;
        if body == b"stream" {
            // Copy the stream through its `endstream` line verbatim.
            let stop = rest.windows(10).position(|w| w == b"\nendstream").map_or(rest.len(), |i| i + 1);
            out.extend_from_slice(&rest[..stop]);
            rest = &rest[stop..];
        }
    }
    flush(&mut run, &mut out);
    out
}

/// `v` on the axis: `log10 v` on a logarithmic one (NaN for `v ≤ 0`, which is then skipped).
fn mapped(scale: Scale, v: f64) -> f64 {
    match scale {
        Scale::Log10 if v > 0.0 => v.log10(),
        Scale::Log10 => f64::NAN,
        Scale::Linear | Scale::Integer => v,
    }
}

/// The panel in axis coordinates (logarithmic axes mapped to `log10`).
fn in_axis_coordinates(panel: &Panel) -> Panel {
    let mut out = panel.clone();
    let (sx, sy) = (panel.x_scale, panel.y_scale);
    for s in &mut out.series {
        for p in &mut s.points {
            *p = (mapped(sx, p.0), mapped(sy, p.1));
        }
    }
    out.x_range = panel.x_range.map(|(a, b)| (mapped(sx, a), mapped(sx, b)));
    out.y_range = panel.y_range.map(|(a, b)| (mapped(sy, a), mapped(sy, b)));
    out
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

/// The label of tick `v` on an axis of `scale` spanning `span` (axis units).
fn tick_label(scale: Scale, v: f64, span: f64) -> String {
    let whole = (v - v.round()).abs() <= 1e-9 * span.max(1.0);
    match scale {
        Scale::Integer if whole => format!("{}", v.round() as i64),
        Scale::Log10 if whole => {
            let k = v.round() as i64;
            let digits: String =
                k.unsigned_abs().to_string().chars().map(|c| SUPERSCRIPTS[c as usize - '0' as usize]).collect();
            format!("10{}{digits}", if k < 0 { "⁻" } else { "" })
        }
        Scale::Integer | Scale::Log10 => String::new(),
        Scale::Linear => {
            // Enough decimals for ticks a tenth of the span apart; "-0" is "0".
            let decimals = if span > 0.0 { (-(span / 10.0).log10()).ceil().clamp(0.0, 12.0) as usize } else { 3 };
            let text = format!("{v:.decimals$}");
            if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
                text.trim_start_matches('-').to_string()
            } else {
                text
            }
        }
    }
}

/// How many ticks an axis asks for: one per whole number on a counting or logarithmic axis with
/// few of them, plotters' default otherwise.
fn tick_count(scale: Scale, (lo, hi): (f64, f64)) -> usize {
    let whole = (hi.floor() - lo.ceil()) as i64 + 1;
    match scale {
        Scale::Integer | Scale::Log10 if (1..=12).contains(&whole) => (hi - lo).ceil().max(1.0) as usize + 1,
        _ => 10,
    }
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let (x_scale, y_scale) = (panel.x_scale, panel.y_scale);
    let panel = &in_axis_coordinates(panel);
    let plot_px =
        (f64::from(size.0 - Y_LABEL_AREA - 2 * MARGIN), f64::from(size.1 - X_LABEL_AREA - CAPTION - 2 * MARGIN));
    let (x, y) = ranges(panel, plot_px);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FAMILY, 15))
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(err)?;
    let (x_span, y_span) = (x.1 - x.0, y.1 - y.0);
    let x_format = move |v: &f64| tick_label(x_scale, *v, x_span);
    let y_format = move |v: &f64| tick_label(y_scale, *v, y_span);
    chart
        .configure_mesh()
        .x_labels(tick_count(x_scale, x))
        .y_labels(tick_count(y_scale, y))
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style((FAMILY, 12))
        .axis_desc_style((FAMILY, 13))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)?;
    let bar_series: Vec<usize> =
        panel.series.iter().enumerate().filter(|(_, s)| s.style == Style::Bars).map(|(i, _)| i).collect();
    let mut labelled = false;
    for (k, s) in panel.series.iter().enumerate() {
        let colour = COLOURS[s.colour.unwrap_or(k) % COLOURS.len()];
        let points: Vec<(f64, f64)> = s.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        let legend = |c: RGBColor| {
            move |(px, py): (i32, i32)| PathElement::new(vec![(px, py), (px + 18, py)], c.stroke_width(2))
        };
        let drawn = match s.style {
            Style::Line => chart.draw_series(LineSeries::new(points, colour.stroke_width(2))).map_err(err)?,
            Style::Dashed => {
                chart.draw_series(DashedLineSeries::new(points, 6, 4, colour.stroke_width(2))).map_err(err)?
            }
            Style::Markers => {
                chart.draw_series(points.into_iter().map(|p| Circle::new(p, 3, colour.filled()))).map_err(err)?
            }
            Style::LineMarkers => {
                chart.draw_series(LineSeries::new(points.clone(), colour.stroke_width(2))).map_err(err)?;
                chart.draw_series(points.into_iter().map(|p| Circle::new(p, 3, colour.filled()))).map_err(err)?
            }
            Style::Bars => {
                let slot = bar_series.iter().position(|&i| i == k).unwrap_or(0) as f64;
                let width = 0.8 / bar_series.len() as f64;
                chart
                    .draw_series(points.into_iter().map(|(px, py)| {
                        let left = px - 0.4 + slot * width;
                        Rectangle::new([(left, 0.0), (left + width, py)], colour.filled())
                    }))
                    .map_err(err)?
            }
        };
        if !s.label.is_empty() {
            drawn.label(&s.label).legend(legend(colour));
            labelled = true;
        }
    }
    if labelled {
        chart
            .configure_series_labels()
            .label_font((FAMILY, 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure() -> Figure {
        Figure::new("test figure", 2)
            .with(
                Panel::new("(a) shape", "X (m)", "Y (m)")
                    .equal_aspect()
                    .with(Series::dashed("undeformed", vec![(0.0, 0.0), (0.5, 0.1), (1.0, 0.0)]))
                    .with(Series::line_markers("loaded", vec![(0.0, 0.0), (0.49, 0.08), (0.98, 0.0)])),
            )
            .with(
                Panel::new("(b) stiffness", "node", "K (N·m/rad)")
                    .with(Series::bars("run 1", vec![(1.0, 100.0), (2.0, 1e4), (3.0, 300.0)]))
                    .with(Series::bars("run 2", vec![(1.0, 200.0), (2.0, 5e3), (3.0, 100.0)])),
            )
    }

    #[test]
    fn draws_labels_series_and_is_deterministic() {
        let a = figure().to_svg().unwrap();
        let b = figure().to_svg().unwrap();
        assert_eq!(a, b);
        for text in ["test figure", "(a) shape", "X (m)", "K (N·m/rad)", "undeformed", "run 2"] {
            assert!(a.contains(text), "missing {text}");
        }
        assert!(a.contains("<polyline") || a.contains("<path"));
        assert!(a.contains("<rect"));
    }

    #[test]
    fn tick_labels_count_whole_numbers_show_decades_and_never_minus_zero() {
        assert_eq!(tick_label(Scale::Integer, 3.0, 10.0), "3");
        assert_eq!(tick_label(Scale::Integer, 2.5, 10.0), "");
        assert_eq!(tick_label(Scale::Log10, 2.0, 2.0), "10²");
        assert_eq!(tick_label(Scale::Log10, -3.0, 2.0), "10⁻³");
        assert_eq!(tick_label(Scale::Log10, 12.0, 2.0), "10¹²");
        assert_eq!(tick_label(Scale::Log10, 2.5, 2.0), "");
        assert_eq!(tick_label(Scale::Linear, -1e-17, 0.2), "0.00");
        assert_eq!(tick_label(Scale::Linear, -0.0, 2.0), "0.0");
        assert_eq!(tick_label(Scale::Linear, -0.05, 0.2), "-0.05");
        assert_eq!(tick_label(Scale::Linear, 150.0, 1000.0), "150");
    }

    #[test]
    fn counting_and_logarithmic_axes_label_only_what_they_should() {
        let stiffness: Vec<(f64, f64)> = (1..=11).map(|j| (j as f64, if j % 3 == 0 { 100.0 } else { 1e4 })).collect();
        let svg = Figure::new("axes", 1)
            .with(
                Panel::new("K", "node j", "K_j (N·m/rad)")
                    .x_integer()
                    .y_log()
                    .with(Series::line_markers("K", stiffness)),
            )
            .to_svg()
            .unwrap();
        for decade in ["10²", "10³", "10⁴"] {
            assert!(svg.contains(&format!(">\n{decade}\n<")), "decade label {decade}");
        }
        for node in 1..=11 {
            assert!(svg.contains(&format!(">\n{node}\n<")), "node label {node}");
        }
        assert!(
            !svg.contains(">\n1.0\n<") && !svg.contains(">\n2.5\n<") && !svg.contains("-0.0"),
            "no fractional labels"
        );
        // Exactly one label per node and per decade (11 + 3), besides the title, the caption, the
        // two axis names and the legend: the empty labels between them are not drawn.
        assert_eq!(svg.matches("<text").count(), 5 + 11 + 3);
    }

    #[test]
    fn the_pdf_is_a_deterministic_vector_page_of_journal_width_with_its_text() {
        let pdf = figure().to_pdf().unwrap();
        assert!(pdf.starts_with(b"%PDF-") && pdf.trim_ascii_end().ends_with(b"%%EOF"));
        let text = String::from_utf8_lossy(&pdf);
        // Two panels side by side: 7 in = 504 pt wide.
        let media = text.split("/MediaBox [").nth(1).and_then(|r| r.split(']').next()).unwrap();
        let numbers: Vec<f64> = media.split_whitespace().map(|v| v.parse().unwrap()).collect();
        assert!((numbers[2] - numbers[0] - 504.0).abs() < 0.5, "{media}");
        // The embedded font travels with it (a subset, as a font file).
        assert!(text.contains("/FontFile2") || text.contains("/FontFile3"), "font embedded");
        // Every object is where the cross-reference table says (the canonical reordering keeps
        // offsets).
        let xref = text.rfind("\nxref\n").unwrap() + 1;
        let table: Vec<&str> = text[xref..].split("trailer").next().unwrap().lines().collect();
        let count: usize = table[1].split_whitespace().nth(1).unwrap().parse().unwrap();
        for (k, entry) in table[2..2 + count].iter().enumerate() {
            let mut fields = entry.split_whitespace();
            let offset: usize = fields.next().unwrap().parse().unwrap();
            if fields.nth(1) == Some("n") {
                assert!(pdf[offset..].starts_with(format!("{k} 0 obj").as_bytes()), "object {k} at {offset}");
            }
        }
        for _ in 0..3 {
            assert!(pdf == figure().to_pdf().unwrap(), "same figure, same bytes");
        }
    }

    #[test]
    fn writes_a_png() {
        let dir = std::env::temp_dir().join(format!("spine-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("f.png");
        figure().write_png(&path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn equal_aspect_gives_equal_scales() {
        let p = figure().panels[0].clone();
        let px = (400.0, 250.0);
        let (x, y) = ranges(&p, px);
        assert!(((x.1 - x.0) / px.0 - (y.1 - y.0) / px.1).abs() < 1e-12);
    }

    #[test]
    fn non_finite_points_are_skipped_not_fatal() {
        let f = Figure::new("nan", 1)
            .with(Panel::new("p", "x", "y").with(Series::line("s", vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)])));
        assert!(f.to_svg().is_ok());
    }
}
