//! Running one checked case and keeping its results as values (not files), so that a figure
//! recipe can draw and check them. Data flows one way: case → solver → [`RunOutput`].

use serde::Serialize;
use spine_case::{DesignSource, DynamicsTask, ValidCase, ValidDesign, ValidDynamics, ValidTwoLink};
use spine_design::adjoint::{adjoint_hand, ReducedGradients};
use spine_design::{solve_design, DesignProblem, DesignResult};
use spine_dynamics::{
    design_damping, design_periodic, periodic_response, step_response, DampingDesign, DynamicProblem, PeriodicDesign,
    PeriodicResponse, StepResponse,
};
use spine_model::{Design, State};

/// Why a run could not give a result.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// The case asks for something impossible (an unstable start, an equilibrium case in a figure).
    Input(String),
    /// A step the case depends on did not succeed (an eq. (33) design that did not end clean).
    Failed(String),
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Input(m) | Self::Failed(m) => f.write_str(m),
        }
    }
}

/// An eq. (33) run with what the figures need besides the solver's result.
#[derive(Clone, Debug, Serialize)]
pub struct StaticDesign {
    pub result: DesignResult,
    /// The start after projection into the bounds, the point the changes are measured from.
    pub start: Design,
    /// `dJ/d(θ0, K)` and `dX_{N+1}/d(θ0, K)` at the optimum (hand adjoint, Appendix I/II).
    #[serde(skip)]
    pub gradients: Option<ReducedGradients>,
    #[serde(skip)]
    pub problem: DesignProblem,
}

/// The design a dynamic run used: given, or from eq. (33) first.
#[derive(Clone, Debug, Serialize)]
pub struct UsedDesign {
    pub design: Design,
    /// Horizontal spans `a_i` of the chain, m (to draw its shapes).
    pub spans: Vec<f64>,
    pub static_design: Option<StaticDesign>,
}

/// A dynamic run: the design it used and what it computed.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "task", rename_all = "snake_case")]
pub enum DynamicOutput {
    Step {
        response: StepResponse,
    },
    Periodic {
        response: PeriodicResponse,
    },
    /// Eq. (35): one design per target, and each design's response to a periodic forcing when the
    /// case gives one.
    Damping {
        designs: Vec<DampingDesign>,
        periodic: Vec<PeriodicResponse>,
    },
    PeriodicDesign {
        design: PeriodicDesign,
    },
}

/// What one run computed.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One value per run: boxing the two-link study as well would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum RunOutput {
    Twolink { study: spine_solve::twolink::Study, stiffness: f64 },
    Design(Box<StaticDesign>),
    Dynamics { used: Box<UsedDesign>, output: DynamicOutput },
}

fn states(result: &DesignResult) -> Option<(State, State)> {
    let (p, l) = (result.passive.as_ref()?, result.loaded.as_ref()?);
    Some((State { theta: p.theta.clone(), lambda: p.lambda }, State { theta: l.theta.clone(), lambda: l.lambda }))
}

/// Eq. (33) from the case's start.
pub fn run_design(valid: &ValidDesign) -> Result<StaticDesign, RunError> {
    let result = solve_design(&valid.problem, &valid.start, valid.formulation, &valid.settings, &mut |_| true)
        .map_err(|e| RunError::Input(format!("solver: {e}")))?;
    let (start, _) = valid.problem.project_start(&valid.start);
    let gradients = states(&result).and_then(|(s1, s2)| adjoint_hand(&valid.problem, &result.design, &s1, &s2).ok());
    Ok(StaticDesign { result, start, gradients, problem: valid.problem.clone() })
}

/// The design of a dynamic case: given, or found by eq. (33) first, which must end clean.
pub fn resolve_design(valid: &ValidDynamics) -> Result<UsedDesign, RunError> {
    match &valid.design {
        DesignSource::Given(d) => {
            Ok(UsedDesign { design: d.clone(), spans: valid.chain.spans.clone(), static_design: None })
        }
        DesignSource::Optimise(v) => {
            let s = run_design(v)?;
            if !s.result.is_clean() {
                return Err(RunError::Failed(format!(
                    "the static design of eq. (33) did not end clean ({}; warnings: {:?}); no dynamics run on it",
                    s.result.solver.status, s.result.warnings
                )));
            }
            Ok(UsedDesign { design: s.result.design.clone(), spans: valid.chain.spans.clone(), static_design: Some(s) })
        }
    }
}

fn dynamics_error(e: spine_dynamics::DynamicsError) -> RunError {
    RunError::Input(format!("design: {e}"))
}

/// The dynamic problem of a case with a resolved design and the given dampers.
pub fn dynamic_problem(valid: &ValidDynamics, design: &Design, damping: &[f64]) -> DynamicProblem {
    DynamicProblem {
        chain: valid.chain.clone(),
        design: design.clone(),
        damping: damping.to_vec(),
        passive: valid.passive.clone(),
        actuation: valid.actuation.clone(),
    }
}

/// Runs a dynamic case (progress of eq. (37) through `progress(done, total)`).
pub fn run_dynamics(valid: &ValidDynamics, progress: &mut dyn FnMut(usize, usize)) -> Result<RunOutput, RunError> {
    let used = resolve_design(valid)?;
    let problem = dynamic_problem(valid, &used.design, &valid.damping);
    let output = match &valid.task {
        DynamicsTask::Simulate if valid.forcing.period().is_none() => {
            DynamicOutput::Step { response: step_response(&problem, &valid.step, false).map_err(dynamics_error)? }
        }
        DynamicsTask::Simulate => DynamicOutput::Periodic {
            response: periodic_response(&problem, valid.forcing.clone(), None, &valid.periodic)
                .map_err(dynamics_error)?,
        },
        DynamicsTask::Damping { targets, settings } => {
            let mut designs = Vec::new();
            let mut periodic = Vec::new();
            for (k, &target) in targets.iter().enumerate() {
                progress(k, targets.len());
                let d = design_damping(&problem, target, settings).map_err(dynamics_error)?;
                if valid.forcing.period().is_some() {
                    let p = dynamic_problem(valid, &used.design, &d.damping);
                    periodic.push(
                        periodic_response(&p, valid.forcing.clone(), None, &valid.periodic).map_err(dynamics_error)?,
                    );
                }
                designs.push(d);
            }
            progress(targets.len(), targets.len());
            DynamicOutput::Damping { designs, periodic }
        }
        DynamicsTask::Periodic { delta_d, method, settings } => {
            let total = match method {
                spine_dynamics::SearchMethod::Ga => settings.ga.generations,
                spine_dynamics::SearchMethod::Pattern => settings.pattern.max_evaluations,
            };
            let design = design_periodic(&problem, valid.forcing.clone(), *delta_d, *method, settings, &mut |p| {
                progress(
                    match method {
                        spine_dynamics::SearchMethod::Ga => p.iteration,
                        spine_dynamics::SearchMethod::Pattern => p.evaluations,
                    },
                    total,
                )
            })
            .map_err(dynamics_error)?;
            DynamicOutput::PeriodicDesign { design }
        }
    };
    Ok(RunOutput::Dynamics { used: Box::new(used), output })
}

/// The two-link study of Sec. 3.
pub fn run_twolink(valid: &ValidTwoLink) -> RunOutput {
    RunOutput::Twolink {
        study: spine_solve::twolink::study(&valid.twolink, valid.stiffness, &valid.deltas, &valid.options),
        stiffness: valid.stiffness,
    }
}

/// Runs any checked case that a figure can hold.
pub fn run(valid: &ValidCase, progress: &mut dyn FnMut(usize, usize)) -> Result<RunOutput, RunError> {
    match valid {
        ValidCase::Twolink(v) => Ok(run_twolink(v)),
        ValidCase::Design(v) => Ok(RunOutput::Design(Box::new(run_design(v)?))),
        ValidCase::Dynamics(v) => run_dynamics(v, progress),
        ValidCase::Equilibrium(_) => {
            Err(RunError::Input("an equilibrium case has no figure recipe; use `spine equilibrium`".into()))
        }
        ValidCase::Figure(_) => Err(RunError::Input("a figure cannot run inside a figure".into())),
    }
}
