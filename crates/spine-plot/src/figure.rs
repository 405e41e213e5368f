//! A figure: a titled grid of panels, drawn to SVG, PNG and PDF.

use crate::draw::{draw_lines, draw_panel};
use crate::error::{err, PlotError};
use crate::layout::{lay_out, FigureLayout};
use crate::panel::Panel;
use crate::pdf::{canonical_pdf, usvg_options};
use crate::style::{register_font, MARGIN};
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

    /// Where everything goes, in pixels: the title's lines, each panel's caption, axes, ranges,
    /// the data's marks and the legend's box. Drawing follows it; [`Figure::check`] reads it.
    pub fn layout(&self) -> FigureLayout {
        register_font();
        lay_out(&self.title, self.columns, &self.panels, self.panel_size)
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &FigureLayout) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        draw_lines(&root, &layout.title, None, f64::from(MARGIN), 10.0)?;
        for (panel, laid) in self.panels.iter().zip(&layout.panels) {
            draw_panel(&root, panel, laid)?;
        }
        root.present().map_err(err)
    }

    /// Draws the figure as an SVG document.
    pub fn to_svg(&self) -> Result<String, PlotError> {
        let layout = self.layout();
        let mut text = String::new();
        self.draw(SVGBackend::with_string(&mut text, layout.size).into_drawing_area(), &layout)?;
        Ok(text)
    }

    /// The figure as a vector PDF (svg2pdf, text set in the embedded font), scaled to a journal's
    /// width: one column (3.5 in) for a single panel, the full text width (7 in) for several.
    pub fn to_pdf(&self) -> Result<Vec<u8>, PlotError> {
        use svg2pdf::usvg;
        let svg = self.to_svg()?;
        let tree = usvg::Tree::from_str(&svg, &usvg_options()).map_err(err)?;
        let width_px = self.size().0;
        let width_in = if self.columns.min(self.panels.len()) <= 1 { 3.5 } else { 7.0 };
        let page = svg2pdf::PageOptions { dpi: width_px as f32 / width_in };
        svg2pdf::to_pdf(&tree, svg2pdf::ConversionOptions::default(), page).map(canonical_pdf).map_err(err)
    }

    /// The figure's size in pixels, `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        self.layout().size
    }

    /// Draws the figure into an RGB buffer (3 bytes per pixel, row by row), text rasterised with
    /// the embedded font; returns its width, height and pixels.
    pub fn to_rgb(&self) -> Result<(u32, u32, Vec<u8>), PlotError> {
        let layout = self.layout();
        let size = layout.size;
        let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
        self.draw(BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area(), &layout)?;
        Ok((size.0, size.1, pixels))
    }

    /// Draws the figure as a PNG file at `path` (text rasterised with the embedded font).
    pub fn write_png(&self, path: &std::path::Path) -> Result<(), PlotError> {
        let layout = self.layout();
        self.draw(BitMapBackend::new(path, layout.size).into_drawing_area(), &layout)
    }
}
