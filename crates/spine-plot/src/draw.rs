//! Drawing a panel with plotters, with the embedded font and the series colours.

use crate::axes::ranges;
use crate::axes::{in_axis_coordinates, tick_count, tick_label};
use crate::error::{err, PlotError};
use crate::panel::Panel;
use crate::series::Style;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// Layout of a figure, px: title band, axis label areas, margins, panel caption.
pub(crate) const TITLE_HEIGHT: u32 = 36;
pub(crate) const X_LABEL_AREA: u32 = 48;
pub(crate) const Y_LABEL_AREA: u32 = 78;
pub(crate) const MARGIN: u32 = 12;
pub(crate) const CAPTION: u32 = 28;

pub(crate) const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");
pub(crate) const FAMILY: &str = "sans-serif";

/// Tableau 10, the colours of successive series.
pub(crate) const COLOURS: [RGBColor; 10] = [
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

pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is a valid TrueType file; a failure here would only lose text.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

pub(crate) fn draw_panel<DB: DrawingBackend>(
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
