//! A figure checked as a reader would look at it: no legend over the data, every text inside the
//! canvas and clear of every other text, and no character the font cannot draw.

use crate::error::{err, PlotError};
use crate::figure::Figure;
use crate::layout::{PanelLayout, Rect};
use crate::pdf::usvg_options;
use crate::text::missing_glyphs;
use svg2pdf::usvg;

/// Something a reader would see wrong in a figure.
#[derive(Clone, Debug, PartialEq)]
pub enum LayoutProblem {
    /// The legend of panel `panel` covers a point, line or bar of series `series`.
    LegendOverData { panel: String, series: String },
    /// A text reaches beyond the canvas (`bbox` as drawn in the SVG, px).
    TextOutside { text: String, bbox: Rect },
    /// Two texts overlap.
    TextOverText { first: String, second: String },
    /// Characters the embedded font has no glyph for (drawn as empty boxes).
    MissingGlyphs { text: String, missing: Vec<char> },
}

impl std::fmt::Display for LayoutProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::LegendOverData { panel, series } => {
                write!(f, "panel \"{panel}\": the legend covers series \"{series}\"")
            }
            Self::TextOutside { text, bbox } => write!(
                f,
                "text \"{text}\" reaches outside the canvas (x {:.1}…{:.1}, y {:.1}…{:.1} px)",
                bbox.x0, bbox.x1, bbox.y0, bbox.y1
            ),
            Self::TextOverText { first, second } => write!(f, "texts \"{first}\" and \"{second}\" overlap"),
            Self::MissingGlyphs { text, missing } => {
                write!(f, "text \"{text}\" has characters the font cannot draw: {missing:?}")
            }
        }
    }
}

/// The texts of an SVG with their boxes as usvg lays them out (the PDF's layout), and its canvas.
struct SvgTexts {
    texts: Vec<(String, Rect)>,
    canvas: Rect,
}

fn svg_texts(svg: &str) -> Result<SvgTexts, PlotError> {
    let tree = usvg::Tree::from_str(svg, &usvg_options()).map_err(err)?;
    fn walk(group: &usvg::Group, out: &mut Vec<(String, Rect)>) {
        for node in group.children() {
            match node {
                usvg::Node::Group(g) => walk(g, out),
                usvg::Node::Text(t) => {
                    let text: String = t.chunks().iter().map(|c| c.text()).collect();
                    let b = t.abs_bounding_box();
                    let bbox =
                        Rect::new(f64::from(b.left()), f64::from(b.top()), f64::from(b.right()), f64::from(b.bottom()));
                    out.push((text, bbox));
                }
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    walk(tree.root(), &mut out);
    let size = tree.size();
    Ok(SvgTexts { texts: out, canvas: Rect::new(0.0, 0.0, f64::from(size.width()), f64::from(size.height())) })
}

fn legend_problems(figure: &Figure, laid: &[PanelLayout]) -> Vec<LayoutProblem> {
    let mut out = Vec::new();
    for (panel, layout) in figure.panels.iter().zip(laid) {
        let Some(legend) = &layout.legend else { continue };
        let mut covered: Vec<usize> =
            layout.marks.iter().filter(|(_, m)| m.hits(&legend.rect)).map(|(k, _)| *k).collect();
        covered.dedup();
        out.extend(covered.into_iter().map(|k| LayoutProblem::LegendOverData {
            panel: panel.title.clone(),
            series: panel.series[k].label.clone(),
        }));
    }
    out
}

impl Figure {
    /// What a reader would see wrong: a legend over data (from [`Figure::layout`]), a text
    /// outside the canvas or over another text (from the SVG as usvg lays it out, the PDF's
    /// text), a character the font cannot draw. Empty for a clean figure.
    pub fn check(&self) -> Result<Vec<LayoutProblem>, PlotError> {
        let layout = self.layout();
        let mut problems = legend_problems(self, &layout.panels);
        let SvgTexts { texts, canvas } = svg_texts(&self.to_svg()?)?;
        for (text, bbox) in &texts {
            if !canvas.holds(bbox, 0.5) {
                problems.push(LayoutProblem::TextOutside { text: text.clone(), bbox: *bbox });
            }
        }
        for (i, (a, ba)) in texts.iter().enumerate() {
            for (b, bb) in &texts[i + 1..] {
                if ba.grown(-1.0).intersects(&bb.grown(-1.0)) {
                    problems.push(LayoutProblem::TextOverText { first: a.clone(), second: b.clone() });
                }
            }
        }
        let written = std::iter::once(&self.title).chain(
            self.panels
                .iter()
                .flat_map(|p| [&p.title, &p.x_label, &p.y_label].into_iter().chain(p.series.iter().map(|s| &s.label))),
        );
        for text in written {
            let missing = missing_glyphs(text);
            if !missing.is_empty() {
                problems.push(LayoutProblem::MissingGlyphs { text: text.clone(), missing });
            }
        }
        Ok(problems)
    }
}
