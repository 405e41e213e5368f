//! Figure recipes: from the runs of a figure case to its panels, CSV tables and checked claims.
//! One module per kind of figure; this one holds the pieces they share.

mod criteria;
mod dynamic;
mod frequency;
mod periodic;
mod pulse;
mod statics;
mod twolink;

use serde_json::Value;
use spine_check::FieldError;
use spine_dynamics::response::Sample;
use spine_model::kinematics::{link_lengths, node_positions};
use spine_model::Design;
use spine_plot::{Figure, Panel, Series};
use spine_run::{
    Claim, DynamicOutput, DynamicsRun, FigureOutput, FigureRecipes, NamedRun, StaticDesign, Table, TwoLinkResult,
    UsedDesign,
};

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
        "fig11" => pulse::pulse_figure(title, runs),
        "fig12" => dynamic::rise_time_figure(title, runs),
        "objectives" => criteria::criteria_figure(title, runs),
        other => Err(FieldError::new("figure", format!("no recipe for {other:?}"))),
    }
}

fn expect_design<'a>(run: &NamedRun<'a>) -> Result<&'a StaticDesign, FieldError> {
    run.output.get::<StaticDesign>().ok_or_else(|| run.error("this figure needs a \"design\" run"))
}

fn expect_dynamics<'a>(run: &NamedRun<'a>) -> Result<(&'a UsedDesign, &'a DynamicOutput), FieldError> {
    let run_of = run.output.get::<DynamicsRun>().ok_or_else(|| run.error("this figure needs a dynamic run"))?;
    Ok((&run_of.used, &run_of.output))
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

    fn table(&self) -> Table {
        let rows = self.unloaded.len().min(self.passive.len()).min(self.loaded.len());
        let x = |p: &[(f64, f64)]| p[..rows].iter().map(|q| q.0).collect::<Vec<_>>();
        let y = |p: &[(f64, f64)]| p[..rows].iter().map(|q| q.1).collect::<Vec<_>>();
        Table::new()
            .counts("node", 1..=rows)
            .numbers("x0_m", x(&self.unloaded))
            .numbers("y0_m", y(&self.unloaded))
            .numbers("x1_m", x(&self.passive))
            .numbers("y1_m", y(&self.passive))
            .numbers("x2_m", x(&self.loaded))
            .numbers("y2_m", y(&self.loaded))
    }
}

fn design_table(design: &Design) -> Table {
    let rows = design.stiffness.len();
    Table::new()
        .counts("index", 1..=rows)
        .optional("theta0_rad", (0..rows).map(|j| design.theta0.get(j).copied()))
        .numbers("stiffness_n_m_per_rad", design.stiffness.iter().copied())
}

fn stiffness_panel(title: &str, series: Vec<Series>) -> Panel {
    series.into_iter().fold(Panel::new(title, "node j", "Kⱼ (N·m/rad)").x_integer().y_log(), Panel::with)
}

/// Panel letters (a), (b), …
fn letter(k: usize) -> char {
    (b'a' + k as u8) as char
}

fn values_table(column: &str, v: &[f64]) -> Table {
    Table::new().counts("index", 1..=v.len()).numbers(column, v.iter().copied())
}

/// End displacement `X − L_x` and the load factor drawn to the scale of `scale` (m).
fn periodic_panel(title: &str, r: &spine_dynamics::PeriodicResponse, scale: f64, target: Option<f64>) -> Panel {
    let t_end = r.samples.last().map_or(0.0, |s| s.t);
    let mut panel = Panel::new(title, "t (s)", spine_run::text::END_DISPLACEMENT)
        .with(Series::line("end-point motion", r.samples.iter().map(|s| (s.t, s.end_displacement)).collect()).colour(0))
        .with(
            Series::dashed(
                format!("load factor s(t) × {scale:.3} m"),
                r.samples.iter().map(|s| (s.t, s.load_factor * scale)).collect(),
            )
            .colour(1),
        );
    if let Some(d) = target {
        panel = panel.with(Series::dashed(format!("δ_d = {d} m"), vec![(0.0, d), (t_end, d)]).colour(3));
    }
    panel
}
