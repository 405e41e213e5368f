//! The house style of every figure: the layout's sizes, the font (embedded, registered once) and
//! the colours of successive series.

use plotters::style::{FontStyle, RGBColor};
use std::sync::Once;

/// Layout of a figure, px: axis label areas (ticks and axis descriptions), margins.
pub(crate) const X_LABEL_AREA: u32 = 48;
pub(crate) const Y_LABEL_AREA: u32 = 78;
pub(crate) const MARGIN: u32 = 12;
/// Font sizes, px (shrunk to fit where a text is too long, down to a floor).
pub(crate) const TITLE_SIZE: f64 = 18.0;
pub(crate) const CAPTION_SIZE: f64 = 15.0;
pub(crate) const AXIS_LABEL_SIZE: f64 = 13.0;
pub(crate) const LEGEND_SIZE: f64 = 12.0;

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
