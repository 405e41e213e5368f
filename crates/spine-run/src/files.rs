//! The files a result writes beside `result.json` (CSV tables, figures).

use spine_dynamics::response::Sample;
use std::fmt::Write as _;

/// A file written beside `result.json`.
pub enum FileContent {
    /// A CSV table or other text.
    Text(String),
    /// A figure, written as `NAME.svg`, `NAME.png` and `NAME.pdf`.
    Figure(spine_plot::Figure),
    /// An animation of the chain's motion, written as `NAME.gif`.
    Animation(crate::animation::Animation),
}

/// A file written beside `result.json`: its name (a figure's stem) and content.
pub struct OutputFile {
    pub name: String,
    pub content: FileContent,
}

impl OutputFile {
    pub fn text(name: impl Into<String>, text: String) -> Self {
        Self { name: name.into(), content: FileContent::Text(text) }
    }
}

/// `t, load_factor, delta, end_displacement, theta_1..theta_N` with full precision.
pub fn samples_csv(samples: &[Sample]) -> String {
    let n = samples.first().map_or(0, |s| s.theta.len());
    let mut text = String::from("t_s,load_factor,delta_m,end_displacement_m");
    for i in 1..=n {
        let _ = write!(text, ",theta_{i}_rad");
    }
    text.push('\n');
    for s in samples {
        let _ = write!(text, "{:e},{:e},{:e},{:e}", s.t, s.load_factor, s.delta, s.end_displacement);
        for t in &s.theta {
            let _ = write!(text, ",{t:e}");
        }
        text.push('\n');
    }
    text
}
