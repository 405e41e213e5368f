//! The files a result writes beside `result.json` (CSV tables, figures).

use spine_dynamics::response::Sample;

/// A file written beside `result.json`.
pub enum FileContent {
    /// A table, written as CSV.
    Table(crate::table::Table),
    /// Text (written as it is).
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

    /// A table, written as CSV under `name`.
    pub fn table(name: impl Into<String>, table: crate::table::Table) -> Self {
        Self { name: name.into(), content: FileContent::Table(table) }
    }
}

/// `t, load_factor, delta, end_displacement, theta_1..theta_N` with full precision.
pub fn samples_table(samples: &[Sample]) -> crate::table::Table {
    let n = samples.first().map_or(0, |s| s.theta.len());
    let mut table = crate::table::Table::new()
        .numbers("t_s", samples.iter().map(|s| s.t))
        .numbers("load_factor", samples.iter().map(|s| s.load_factor))
        .numbers("delta_m", samples.iter().map(|s| s.delta))
        .numbers("end_displacement_m", samples.iter().map(|s| s.end_displacement));
    for i in 0..n {
        table = table.numbers(format!("theta_{}_rad", i + 1), samples.iter().map(|s| s.theta[i]));
    }
    table
}
