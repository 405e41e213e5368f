//! Text as the figure lays it out: widths in the embedded font, lines wrapped and shrunk to fit a
//! width, and the characters the font cannot draw.

use crate::style::{register_font, FAMILY, FONT};
use ab_glyph::Font as _;
use plotters::style::IntoFont;

/// Width of `text` set at `size` px, as plotters' bitmap backend lays it out (advances and
/// kerning of the embedded font). The SVG and PDF set the same text about 6 % narrower, so a text
/// that fits by this measure fits in every format.
pub(crate) fn width(text: &str, size: f64) -> f64 {
    register_font();
    (FAMILY, size).into_font().box_size(text).map_or(0.0, |(w, _)| f64::from(w))
}

/// `text` broken at spaces into lines no wider than `max_width` at `size` (a single word wider
/// than that stays whole on its line).
pub(crate) fn wrap(text: &str, size: f64, max_width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        let candidate = if line.is_empty() { word.to_string() } else { format!("{line} {word}") };
        if line.is_empty() || width(&candidate, size) <= max_width {
            line = candidate;
        } else {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

/// A text fitted to a width: its lines and the font size they are set at.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedText {
    pub lines: Vec<String>,
    /// px
    pub size: f64,
}

impl FittedText {
    /// `text` at the largest size from `size` down to `min_size` (1 px steps) at which it wraps
    /// into at most `max_lines` lines no wider than `max_width`; at `min_size`, wrapped, when no
    /// size does.
    pub(crate) fn fit(text: &str, size: f64, min_size: f64, max_lines: usize, max_width: f64) -> Self {
        let mut s = size;
        loop {
            let lines = wrap(text, s, max_width);
            let fits = lines.len() <= max_lines && lines.iter().all(|l| width(l, s) <= max_width);
            if fits || s - 1.0 < min_size {
                return Self { lines, size: s };
            }
            s -= 1.0;
        }
    }

    /// Distance between baselines, px.
    pub(crate) fn line_height(&self) -> f64 {
        (1.25 * self.size).ceil()
    }

    /// Height of the block, px.
    pub(crate) fn height(&self) -> f64 {
        self.line_height() * self.lines.len() as f64
    }
}

/// The characters of `text` that the embedded font has no glyph for (drawn as empty boxes).
pub fn missing_glyphs(text: &str) -> Vec<char> {
    let Ok(font) = ab_glyph::FontRef::try_from_slice(FONT) else {
        return Vec::new();
    };
    let mut missing: Vec<char> = text.chars().filter(|c| !c.is_whitespace() && font.glyph_id(*c).0 == 0).collect();
    missing.dedup();
    missing
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_title_wraps_within_its_width_and_a_short_one_stays_whole() {
        let title = "Fig. 10: 7-link structure, nodal stiffness optimised under a periodic load, eq. (37), by a genetic algorithm (the paper's), with a design by exact gradients beside it";
        let fitted = FittedText::fit(title, 18.0, 14.0, 2, 1096.0);
        assert!(fitted.lines.len() == 2 && fitted.size <= 18.0, "{fitted:?}");
        assert!(fitted.lines.iter().all(|l| width(l, fitted.size) <= 1096.0));
        assert_eq!(fitted.lines.join(" "), title);
        assert_eq!(FittedText::fit("short", 18.0, 14.0, 1, 500.0).lines, vec!["short".to_string()]);
        assert!(width("wide text", 18.0) > width("wide text", 12.0));
    }

    #[test]
    fn the_font_draws_the_papers_symbols_and_reports_what_it_cannot() {
        assert!(missing_glyphs("θ₀ θ₁ θ₂ Kⱼ Cⱼ T₉₀ δ Δ∞ ‖θ₀‖ N·m/rad² −×≤").is_empty());
        assert_eq!(missing_glyphs("a\u{1D4AF}b"), vec!['\u{1D4AF}']);
    }
}
