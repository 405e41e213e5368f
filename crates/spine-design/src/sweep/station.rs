//! One point of a followed sweep: the optimum at one parameter value, re-solved tightly from a
//! predicted point, with its sensitivity to the swept parameter (the next tangent), its active
//! set, second-order sufficiency and the stability of its equilibria.

use super::{Sweep, SweepError};
use crate::certificate::CertifiedPoint;
use crate::full_space::Multipliers;
use crate::layout::StateForm;
use crate::problem::DesignProblem;
use crate::result::DesignResult;
use crate::sensitivity::{sensitivities, Derivative, Optimum, Parameter, SensitivityReport};
use crate::settings::{warm_point_options, ExtraOption};
use crate::solve::polish::{polish, tight_settings};
use crate::solve::run::{resolve_from, FullPoint};
use crate::solve::settle::certify_run;
use crate::solver_run::SolverRun;
use spine_model::{Design, State};

/// The optimum at one parameter value.
pub(crate) struct Station {
    pub parameter: f64,
    pub run: SolverRun,
    pub result: DesignResult,
    /// Its sensitivity to the swept parameter (`None` when the optimum is not clean).
    pub report: Option<SensitivityReport>,
}

/// Where the corrector starts: a design, both states, Ipopt's multipliers.
pub(crate) struct Prediction {
    pub form: StateForm,
    pub design: Design,
    pub states: (State, State),
    pub multipliers: Option<Multipliers>,
}

impl Station {
    pub fn clean(&self) -> bool {
        self.result.is_clean() && self.report.is_some()
    }

    /// The strictly active inequality bounds (empty when not clean).
    pub fn active(&self) -> Vec<String> {
        self.report.as_ref().map(|r| r.active.clone()).unwrap_or_default()
    }

    /// Second-order sufficiency of the optimum (the reduced KKT matrix's inertia).
    pub fn second_order(&self) -> bool {
        self.report.as_ref().is_some_and(|r| r.conditions.second_order_sufficient)
    }

    /// Whether the passive and the loaded equilibrium are stable.
    pub fn stable(&self) -> [bool; 2] {
        let s = |r: &Option<crate::result::StateReport>| r.as_ref().is_some_and(|r| r.stability.stable);
        [s(&self.result.passive), s(&self.result.loaded)]
    }

    /// The derivative along the sweep in the direction of `step`'s sign: two-sided where the
    /// conditions hold, else the one-sided one for that direction.
    pub fn tangent(&self, step: f64) -> Option<&Derivative> {
        let p = self.report.as_ref()?.parameters.first()?;
        p.derivative.as_ref().or(if step >= 0.0 { p.increase.as_ref() } else { p.decrease.as_ref() })
    }

    /// The first-order prediction of the optimum at `parameter` (the tangent's step from here; no
    /// step where there is no tangent), with this optimum's multipliers.
    pub fn predict(&self, parameter: f64) -> Prediction {
        let delta = parameter - self.parameter;
        let (design, (passive, loaded)) = (&self.result.design, self.states());
        let moved = |v: &[f64], d: Option<&Vec<f64>>| -> Vec<f64> {
            v.iter().enumerate().map(|(i, x)| x + d.map_or(0.0, |d| delta * d[i])).collect()
        };
        let t = self.tangent(delta);
        let lambda = |l: f64, d: Option<f64>| l + d.map_or(0.0, |d| delta * d);
        Prediction {
            form: self.form(),
            design: Design {
                theta0: moved(&design.theta0, t.map(|t| &t.theta0)),
                stiffness: moved(&design.stiffness, t.map(|t| &t.stiffness)),
            },
            states: (
                State {
                    theta: moved(&passive.theta, t.map(|t| &t.theta1)),
                    lambda: lambda(passive.lambda, t.map(|t| t.lambda1)),
                },
                State {
                    theta: moved(&loaded.theta, t.map(|t| &t.theta2)),
                    lambda: lambda(loaded.lambda, t.map(|t| t.lambda2)),
                },
            ),
            multipliers: self.run.multipliers.clone(),
        }
    }

    fn form(&self) -> StateForm {
        self.run.solver.state_variables.unwrap_or(StateForm::Absolute)
    }

    fn states(&self) -> (State, State) {
        // Invariant: a station's run is a full-space re-solve (`resolve_from`, `polish`), which
        // always returns both states.
        self.run.states.clone().expect("a full-space run has both states")
    }
}

impl Sweep<'_> {
    /// A tight solve at `parameter` from `design` alone (start states by continuation, fresh
    /// multipliers): the first station (the given optimum re-solved from itself), and the restart
    /// after a jump.
    pub(crate) fn restart(&self, parameter: f64, design: &Design) -> Result<Station, SweepError> {
        let problem = self.problem(parameter)?;
        let run = polish(&problem, design, self.solver).map_err(SweepError::Solver)?;
        self.station(parameter, &problem, run)
    }

    /// The corrector: the optimum at `parameter` from `prediction`, warm-started with the
    /// predicted multipliers and a small barrier parameter.
    pub(crate) fn settle(&self, parameter: f64, prediction: &Prediction) -> Result<Station, SweepError> {
        let problem = self.problem(parameter)?;
        let mut settings = tight_settings(self.solver);
        for (name, value) in warm_point_options(self.settings.mu_init, 1e-9) {
            settings.ipopt_options.entry(name.into()).or_insert(ExtraOption::Num(value));
        }
        if prediction.multipliers.is_some() {
            settings.ipopt_options.insert("warm_start_init_point".into(), ExtraOption::Str("yes".into()));
        }
        let point = FullPoint {
            form: prediction.form,
            design: &prediction.design,
            states: &prediction.states,
            multipliers: prediction.multipliers.as_ref(),
            springs: settings.spring_variables.resolve(&problem),
        };
        let run = resolve_from(&problem, point, &settings.ipopt()).map_err(SweepError::Solver)?;
        self.station(parameter, &problem, run)
    }

    /// A converged run checked, and differentiated with respect to the swept parameter where clean.
    fn station(&self, parameter: f64, problem: &DesignProblem, run: SolverRun) -> Result<Station, SweepError> {
        let mut result = run.clone().check(problem, self.solver);
        if result.solver.converged {
            result.certificate = certify_run(problem, &run, CertifiedPoint::Run).map(|(c, _)| c);
        }
        let report = match (&run.multipliers, run.point(problem), result.is_clean()) {
            (Some(multipliers), Some((layout, x)), true) => {
                let optimum = Optimum { problem, layout, x: &x, multipliers };
                let tangent = (self.tangent_at)(parameter).map_err(SweepError::Parameter)?;
                let swept = Parameter { name: self.name.to_string(), value: parameter, tangent };
                Some(sensitivities(&optimum, &[swept])?)
            }
            _ => None,
        };
        Ok(Station { parameter, run, result, report })
    }

    /// How far the corrector moved from the prediction, as a fraction of the design box: the
    /// largest change of an angle over `2 θ0_max` and of a stiffness over its bounds' range.
    pub(crate) fn distance(&self, station: &Station, prediction: &Prediction) -> f64 {
        let (design, b) = (&station.result.design, &self.bounds);
        let angles =
            design.theta0.iter().zip(&prediction.design.theta0).map(|(a, p)| (a - p).abs() / (2.0 * b.theta0_max));
        let springs = design.stiffness.iter().zip(&prediction.design.stiffness).enumerate().map(|(j, (k, p))| {
            let range = (b.stiffness_max[j] - b.stiffness_min[j]).abs().max(f64::MIN_POSITIVE);
            (k - p).abs() / range
        });
        angles.chain(springs).fold(0.0, f64::max)
    }
}
