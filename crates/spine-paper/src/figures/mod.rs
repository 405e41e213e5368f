//! Figure recipes: from the runs of a figure case to its panels, CSV tables and checked claims.
//! One module per kind of figure; this one holds the pieces they share.

mod dynamic;
mod periodic;
mod statics;
mod twolink;

use serde_json::Value;
use spine_check::FieldError;
use spine_dynamics::response::Sample;
use spine_model::kinematics::{link_lengths, node_positions};
use spine_model::Design;
use spine_plot::{Figure, Panel, Series};
use spine_run::{Claim, DynamicOutput, FigureOutput, FigureRecipes, NamedRun, RunOutput, StaticDesign, UsedDesign};
use std::fmt::Write as _;

/// The paper's recipes, by figure name: what `spine case` and `flexspine` pass to the run path.
#[derive(Clone, Copy, Debug, Default)]
pub struct PaperFigures;

impl FigureRecipes for PaperFigures {
    fn draw(&self, figure: &str, title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
        recipe(figure, title, runs)
    }
}

/// Draws the runs of figure `figure`. Errors say which run does not fit the recipe.
pub fn recipe(figure: &str, title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
    match figure {
        "twolink" => twolink::figure(title, runs),
        "fig3" | "fig4" | "fig6" | "fig7" | "fig8" => statics::design_figure(figure, title, runs),
        "fig5" => statics::load_sweep_figure(title, runs),
        "fig9" => dynamic::step_designs_figure(title, runs),
        "fig10" => periodic::periodic_design_figure(title, runs),
        "fig11" => dynamic::pulse_figure(title, runs),
        "fig12" => dynamic::rise_time_figure(title, runs),
        other => Err(FieldError::new("figure", format!("no recipe for {other:?}"))),
    }
}

fn expect_design<'a>(run: &NamedRun<'a>) -> Result<&'a StaticDesign, FieldError> {
    match run.output {
        RunOutput::Design(s) => Ok(s),
        _ => Err(run.error("this figure needs a \"design\" run")),
    }
}

fn expect_dynamics<'a>(run: &NamedRun<'a>) -> Result<(&'a UsedDesign, &'a DynamicOutput), FieldError> {
    match run.output {
        RunOutput::Dynamics { used, output } => Ok((used, output)),
        _ => Err(run.error("this figure needs a dynamic run")),
    }
}

fn points(ys: &[f64], first_index: usize) -> Vec<(f64, f64)> {
    ys.iter().enumerate().map(|(i, y)| ((i + first_index) as f64, *y)).collect()
}

fn nodes_of(spans: &[f64], theta0: &[f64], theta: &[f64]) -> Vec<(f64, f64)> {
    node_positions(&link_lengths(spans, theta0), theta)
}

/// The three shapes of a design: unloaded `θ0`, passive `θ1`, loaded `θ2` (node coordinates, m).
pub struct Shapes {
    pub unloaded: Vec<(f64, f64)>,
    pub passive: Vec<(f64, f64)>,
    pub loaded: Vec<(f64, f64)>,
}

impl Shapes {
    fn of_static(s: &StaticDesign) -> Option<Self> {
        Some(Shapes {
            unloaded: s.result.unloaded_nodes.clone(),
            passive: s.result.passive.as_ref()?.nodes.clone(),
            loaded: s.result.loaded.as_ref()?.nodes.clone(),
        })
    }

    fn of_ends(spans: &[f64], design: &Design, ends: &spine_dynamics::response::StaticEnds) -> Self {
        let t0 = &design.theta0;
        Shapes {
            unloaded: nodes_of(spans, t0, t0),
            passive: nodes_of(spans, t0, &ends.theta1),
            loaded: nodes_of(spans, t0, &ends.theta2),
        }
    }

    fn panel(&self, title: &str) -> Panel {
        Panel::new(title, "X (m)", "Y (m)")
            .equal_aspect()
            .with(Series::dashed("unloaded θ₀", self.unloaded.clone()).colour(7))
            .with(Series::line_markers("passive load θ₁", self.passive.clone()).colour(0))
            .with(Series::line_markers("passive + axial θ₂", self.loaded.clone()).colour(3))
    }

    fn csv(&self) -> String {
        let mut text = String::from("node,x0_m,y0_m,x1_m,y1_m,x2_m,y2_m\n");
        for (j, ((a, b), c)) in self.unloaded.iter().zip(&self.passive).zip(&self.loaded).enumerate() {
            let _ = writeln!(text, "{},{:e},{:e},{:e},{:e},{:e},{:e}", j + 1, a.0, a.1, b.0, b.1, c.0, c.1);
        }
        text
    }
}

fn design_csv(design: &Design) -> String {
    let mut text = String::from("index,theta0_rad,stiffness_n_m_per_rad\n");
    for (j, k) in design.stiffness.iter().enumerate() {
        let t = design.theta0.get(j).map_or(String::new(), |t| format!("{t:e}"));
        let _ = writeln!(text, "{},{t},{k:e}", j + 1);
    }
    text
}

fn stiffness_panel(title: &str, series: Vec<Series>) -> Panel {
    series.into_iter().fold(Panel::new(title, "node j", "Kⱼ (N·m/rad)").x_integer().y_log(), Panel::with)
}

/// Panel letters (a), (b), …
fn letter(k: usize) -> char {
    (b'a' + k as u8) as char
}
