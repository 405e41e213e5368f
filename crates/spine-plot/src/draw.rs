//! Drawing a panel with plotters, with the embedded font and the series colours.

use crate::axes::{in_axis_coordinates, tick_count, tick_label};
use crate::error::{err, PlotError};
use crate::layout::{bar, bar_base, LegendLayout, PanelLayout};
use crate::panel::Panel;
use crate::series::{Series, Style};
use crate::style::{COLOURS, FAMILY, LEGEND_SIZE, X_LABEL_AREA, Y_LABEL_AREA};
use crate::text::FittedText;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Draws `lines` of `size` px centred on `centre_x`, the first line's top at `top`.
pub(crate) fn draw_lines<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &FittedText,
    centre_x: Option<f64>,
    left: f64,
    top: f64,
) -> Result<(), PlotError> {
    let pos = match centre_x {
        Some(_) => Pos::new(HPos::Center, VPos::Top),
        None => Pos::new(HPos::Left, VPos::Top),
    };
    let style = (FAMILY, text.size).into_font().color(&BLACK).pos(pos);
    for (k, line) in text.lines.iter().enumerate() {
        let x = centre_x.unwrap_or(left);
        let y = top + k as f64 * text.line_height();
        root.draw_text(line, &style, (x.round() as i32, y.round() as i32)).map_err(err)?;
    }
    Ok(())
}

fn px(p: (f64, f64)) -> (i32, i32) {
    (p.0.round() as i32, p.1.round() as i32)
}

/// Draws `panel` where `layout` puts it: caption, axes, ticks, series and legend.
pub(crate) fn draw_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panel: &Panel,
    layout: &PanelLayout,
) -> Result<(), PlotError> {
    let (x_scale, y_scale) = (panel.x_scale, panel.y_scale);
    let panel = &in_axis_coordinates(panel);
    let centre = 0.5 * (layout.cell.x0 + layout.cell.x1);
    draw_lines(root, &layout.caption, Some(centre), 0.0, layout.caption_top)?;
    let c = &layout.chart;
    let area = root.clone().shrink(px((c.x0, c.y0)), (c.width().round() as u32, c.height().round() as u32));
    let (x, y) = (layout.x, layout.y);
    let mut chart = ChartBuilder::on(&area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(err)?;
    let (x_span, y_span) = (x.1 - x.0, y.1 - y.0);
    let x_format = move |v: &f64| tick_label(x_scale, *v, x_span);
    let y_format = move |v: &f64| tick_label(y_scale, *v, y_span);
    chart
        .configure_mesh()
        .x_labels(tick_count(x_scale, x, layout.plot.width(), 60.0))
        .y_labels(tick_count(y_scale, y, layout.plot.height(), 28.0))
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style((FAMILY, 12))
        .axis_desc_style((FAMILY, layout.x_label_size.min(layout.y_label_size)))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)?;
    let bar_series: Vec<usize> =
        panel.series.iter().enumerate().filter(|(_, s)| s.style == Style::Bars).map(|(i, _)| i).collect();
    let base = bar_base(y_scale, y);
    // Bars under lines, dashed reference curves over solid ones (so both show), markers on top;
    // the legend keeps the panel's order.
    let rank = |style: Style| match style {
        Style::Bars => 0,
        Style::Line | Style::LineMarkers => 1,
        Style::Dashed => 2,
        Style::Markers => 3,
    };
    let mut order: Vec<usize> = (0..panel.series.len()).collect();
    order.sort_by_key(|&k| rank(panel.series[k].style));
    for (k, s) in order.into_iter().map(|k| (k, &panel.series[k])) {
        let colour = colour(s, k);
        let points: Vec<(f64, f64)> = s.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
        match s.style {
            Style::Line => {
                chart.draw_series(LineSeries::new(points, colour.stroke_width(2))).map_err(err)?;
            }
            Style::Dashed => {
                chart.draw_series(DashedLineSeries::new(points, 6, 4, colour.stroke_width(2))).map_err(err)?;
            }
            Style::Markers => {
                chart.draw_series(points.into_iter().map(|p| Circle::new(p, 3, colour.filled()))).map_err(err)?;
            }
            Style::LineMarkers => {
                chart.draw_series(LineSeries::new(points.clone(), colour.stroke_width(2))).map_err(err)?;
                chart.draw_series(points.into_iter().map(|p| Circle::new(p, 3, colour.filled()))).map_err(err)?;
            }
            Style::Bars => {
                let slot = bar_series.iter().position(|&i| i == k).unwrap_or(0);
                chart
                    .draw_series(points.into_iter().map(|(bx, by)| {
                        let (a, b) = bar(bx, by, base, slot, bar_series.len());
                        Rectangle::new([a, b], colour.filled())
                    }))
                    .map_err(err)?;
            }
        }
    }
    if let Some(legend) = &layout.legend {
        draw_legend(root, panel, legend)?;
    }
    Ok(())
}

fn colour(s: &Series, k: usize) -> RGBColor {
    COLOURS[s.colour.unwrap_or(k) % COLOURS.len()]
}

/// A legend: its box, and per entry a swatch drawn as the series is and its label.
fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panel: &Panel,
    legend: &LegendLayout,
) -> Result<(), PlotError> {
    let r = &legend.rect;
    root.draw(&Rectangle::new([px((r.x0, r.y0)), px((r.x1, r.y1))], WHITE.mix(0.9).filled())).map_err(err)?;
    root.draw(&Rectangle::new([px((r.x0, r.y0)), px((r.x1, r.y1))], BLACK.mix(0.4))).map_err(err)?;
    let text = (FAMILY, LEGEND_SIZE).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for e in &legend.entries {
        let s = &panel.series[e.series];
        let c = colour(s, e.series);
        let (w, mid) = (&e.swatch, 0.5 * (e.swatch.y0 + e.swatch.y1));
        let line = |a: f64, b: f64| PathElement::new(vec![px((a, mid)), px((b, mid))], c.stroke_width(2));
        match s.style {
            Style::Line => root.draw(&line(w.x0, w.x1)).map_err(err)?,
            Style::Dashed => {
                root.draw(&line(w.x0, w.x0 + 7.0)).map_err(err)?;
                root.draw(&line(w.x1 - 7.0, w.x1)).map_err(err)?;
            }
            Style::Markers => {
                root.draw(&Circle::new(px((0.5 * (w.x0 + w.x1), mid)), 3, c.filled())).map_err(err)?;
            }
            Style::LineMarkers => {
                root.draw(&line(w.x0, w.x1)).map_err(err)?;
                root.draw(&Circle::new(px((0.5 * (w.x0 + w.x1), mid)), 3, c.filled())).map_err(err)?;
            }
            Style::Bars => {
                root.draw(&Rectangle::new([px((w.x0 + 3.0, w.y0)), px((w.x1 - 3.0, w.y1))], c.filled()))
                    .map_err(err)?;
            }
        }
        root.draw_text(&s.label, &text, px(e.label_at)).map_err(err)?;
    }
    Ok(())
}
