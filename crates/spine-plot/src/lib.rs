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
//! Further modules:
//!
//! * `axes`: Axis ranges, scales and tick labels (linear, counting, logarithmic).
//! * `draw`: Drawing a panel with plotters, with the embedded font and the series colours.
//! * `error`: Why a figure could not be drawn.
//! * `gif`: Animated GIF from a sequence of figures of one size (the frames of a motion).
//! * `pdf`: svg2pdf's output made deterministic: its hash-ordered resource dictionaries sorted in
//!   place.
//! * `series`: A series of `(x, y)` points and how it is drawn.
//! * `style`: The house style of every figure: the layout's sizes, the font (embedded, registered
//!   once) and the colours of successive series.
//! * `check`: A figure checked as a reader would look at it: no legend over the data, every text
//!   inside the canvas and clear of every other text, and no character the font cannot draw.
//! * `figure`: A figure: a titled grid of panels, drawn to SVG, PNG and PDF.
//! * `layout`: Where everything of a figure goes, in pixels: the title's lines, each panel's
//!   caption, axes box and axis ranges, the marks the data makes, and the legend's box, placed in a
//!   corner no data reaches or, when every corner is taken, below the axes.
//! * `panel`: A panel: axes with their labels and scales, and the series drawn on them.
//! * `text`: Text as the figure lays it out: widths in the embedded font, lines wrapped and shrunk
//!   to fit a width, and the characters the font cannot draw.
//!
//! ```
//! use spine_plot::{Figure, Panel, Series};
//! let panel = Panel::new("(a) a line", "x (m)", "y (m)")
//!     .with(Series::line("y = x²", (0..=10).map(|i| (i as f64, (i * i) as f64)).collect()));
//! let svg = Figure::new("example", 1).with(panel).to_svg().unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```
#![forbid(unsafe_code)]

mod axes;
mod check;
mod draw;
mod error;
mod figure;
mod gif;
mod layout;
mod panel;
mod pdf;
mod series;
mod style;
mod text;

pub use check::LayoutProblem;
pub use error::PlotError;
pub use figure::Figure;
pub use gif::to_gif;
pub use layout::{FigureLayout, LegendEntry, LegendLayout, Mark, PanelLayout, Rect};
pub use panel::{LegendPlace, Panel, Scale};
pub use series::{Series, Style};
pub use text::{missing_glyphs, FittedText};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::axes::*;

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
        for decade in ["10¹", "10²", "10³", "10⁴"] {
            assert!(svg.contains(&format!(">\n{decade}\n<")), "decade label {decade}");
        }
        for node in 1..=11 {
            assert!(svg.contains(&format!(">\n{node}\n<")), "node label {node}");
        }
        assert!(
            !svg.contains(">\n1.0\n<") && !svg.contains(">\n2.5\n<") && !svg.contains("-0.0"),
            "no fractional labels"
        );
        // Exactly one label per node and per decade (11 + 4: the axis starts a decade below the
        // smallest K), besides the title, the caption, the two axis names and the legend: the
        // empty labels between them are not drawn.
        assert_eq!(svg.matches("<text").count(), 5 + 11 + 4);
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
    fn equal_aspect_gives_equal_scales_in_a_box_fitted_to_the_data() {
        let layout = figure().layout();
        let p = &layout.panels[0];
        assert!(
            ((p.x.1 - p.x.0) / p.plot.width() - (p.y.1 - p.y.0) / p.plot.height()).abs()
                < 0.01 * (p.x.1 - p.x.0) / p.plot.width()
        );
        // The y range is the data's (0 … 0.1 m with its margin), not widened to the panel.
        assert!(p.y.0 > -0.01 && p.y.1 < 0.11, "{:?}", p.y);
    }

    #[test]
    fn a_logarithmic_bar_axis_starts_a_decade_below_the_smallest_bar() {
        let mut f = figure();
        f.panels[1] = f.panels[1].clone().y_log();
        let layout = f.layout();
        let p = &layout.panels[1];
        assert!(layout.panels[1].marks.iter().all(|(_, m)| matches!(m, Mark::Box(r) if r.y1 <= p.plot.y1 + 0.5)));
        assert_eq!(p.y.0, 1.0, "K from 100: the axis starts at 10¹, not at 10⁰");
        assert!(p.y.1 > 4.0 && p.y.1 < 4.2);
    }

    #[test]
    fn the_legend_goes_where_no_data_is_or_below_the_axes() {
        // A line across the whole panel takes every corner: the legend goes below.
        let crowded = Figure::new("legend", 1).with(
            Panel::new("p", "x", "y")
                .with(Series::line("up", (0..=20).map(|i| (f64::from(i), f64::from(i))).collect()))
                .with(Series::line("down", (0..=20).map(|i| (f64::from(i), f64::from(20 - i))).collect()))
                .with(Series::line("top", vec![(0.0, 20.0), (20.0, 20.0)]))
                .with(Series::line("bottom", vec![(0.0, 0.0), (20.0, 0.0)])),
        );
        let layout = crowded.layout();
        let legend = layout.panels[0].legend.as_ref().unwrap();
        assert_eq!(legend.place, LegendPlace::Below);
        assert!(legend.rect.y0 >= layout.panels[0].chart.y1, "below the tick labels");
        assert!(crowded.check().unwrap().is_empty(), "{:?}", crowded.check());
        // A falling curve leaves the upper right free.
        let falling = Figure::new("legend", 1).with(
            Panel::new("p", "x", "y")
                .with(Series::line("fall", (0..=20).map(|i| (f64::from(i), (-f64::from(i)).exp())).collect())),
        );
        assert_eq!(falling.layout().panels[0].legend.as_ref().unwrap().place, LegendPlace::UpperRight);
        // Pinned over the data, the check says so.
        let pinned = Figure::new("legend", 1).with(
            Panel::new("p", "x", "y")
                .legend_at(LegendPlace::UpperLeft)
                .with(Series::line("fall", (0..=20).map(|i| (f64::from(i), (-f64::from(i)).exp())).collect())),
        );
        let problems = pinned.check().unwrap();
        assert!(
            matches!(&problems[..], [LayoutProblem::LegendOverData { series, .. }] if series == "fall"),
            "{problems:?}"
        );
    }

    #[test]
    fn a_title_too_long_for_the_canvas_wraps_and_the_check_finds_text_outside_or_unprintable() {
        let long = "A title far too long for one line of a two-panel figure, which a journal would not print cut off at the right edge of the page, however wide the page and however small the type";
        let mut f = figure();
        f.title = long.into();
        assert!(f.layout().title.lines.len() == 2);
        assert!(f.check().unwrap().is_empty(), "{:?}", f.check());
        f.panels[0].x_label = format!("x {}", '\u{1D4AF}');
        let problems = f.check().unwrap();
        assert!(problems.iter().any(|p| matches!(p, LayoutProblem::MissingGlyphs { .. })), "{problems:?}");
    }

    #[test]
    fn non_finite_points_are_skipped_not_fatal() {
        let f = Figure::new("nan", 1)
            .with(Panel::new("p", "x", "y").with(Series::line("s", vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)])));
        assert!(f.to_svg().is_ok());
    }
}
