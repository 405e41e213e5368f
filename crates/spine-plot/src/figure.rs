//! A figure: a titled grid of panels, drawn to SVG, PNG and PDF.

use crate::draw::{draw_panel, register_font, FAMILY, FONT, MARGIN, TITLE_HEIGHT};
use crate::error::{err, PlotError};
use crate::panel::Panel;
use crate::pdf::canonical_pdf;
use plotters::coord::Shift;
use plotters::prelude::*;

/// A grid of panels, filled row by row.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    pub title: String,
    pub columns: usize,
    pub panels: Vec<Panel>,
    /// Size of one panel, px.
    pub panel_size: (u32, u32),
}

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
