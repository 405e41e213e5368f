//! `"kind": "simulate" | "damping" | "periodic"`: the dynamics of Sec. 5.2 — a step or periodic
//! response, the damping design of eq. (35), the periodic-load design of eq. (37).

pub use crate::dynamics_specs::{DampingDesignSpec, PeriodicDesignSpec, StaticDesignSpec};

use crate::design_case::{DesignCase, MultiStartSpec, ValidDesign};
use crate::dynamics_checks::{check_periodic, check_periodic_forcing, check_simulation, MAX_T_END};
use crate::error::CaseError;
use crate::per_item::PerItem;
use crate::specs::{non_negative, positive, ChainSpec, DesignSpec, LoadSpec, Notes};
use serde::{Deserialize, Serialize};
use spine_dynamic_design::{DampingSettings, PeriodicDesignSettings, SearchMethod};
use spine_dynamics::{Forcing, PeriodicSettings, StepSettings};
use spine_model::{Chain, Design, NodalLoads};

fn step() -> Forcing {
    Forcing::Step
}

/// A dynamic case (kinds `simulate`, `damping`, `periodic`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DynamicsCase {
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    /// The chain; every link needs a mass > 0.
    pub chain: ChainSpec,
    /// A given design, or `"optimise"` with a `static_design` section (eq. (33) first).
    pub design: DesignSpec,
    #[serde(default)]
    pub static_design: Option<StaticDesignSpec>,
    pub loads: LoadSpec,
    /// Dampers `C_1..C_{N+1}`, N·m·s/rad: one number or `N + 1`, each ≥ 0.
    pub damping: PerItem,
    /// Time profile of the axial force (default: a step at `t = 0`). In a `damping` case eq. (35)
    /// designs the step response; a periodic forcing here is then simulated on each design.
    #[serde(default = "step")]
    pub forcing: Forcing,
    /// Step response settings (also used by every evaluation of eq. (35)).
    #[serde(default)]
    pub simulation: StepSettings,
    /// Periodic response settings (kind `simulate` with a periodic forcing).
    #[serde(default)]
    pub periodic: PeriodicSettings,
    #[serde(default)]
    pub damping_design: Option<DampingDesignSpec>,
    #[serde(default)]
    pub periodic_design: Option<PeriodicDesignSpec>,
}

/// The three dynamic kinds: one case format, three tasks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DynamicKind {
    /// A step or periodic response (Sec. 5.2).
    Simulate,
    /// The damping design, eq. (35).
    Damping,
    /// The periodic-load design, eq. (37).
    Periodic,
}

impl DynamicKind {
    /// The kind's name in a case file.
    pub fn name(self) -> &'static str {
        match self {
            Self::Simulate => "simulate",
            Self::Damping => "damping",
            Self::Periodic => "periodic",
        }
    }
}

/// Where the design of a dynamic case comes from.
#[derive(Clone, Debug)]
pub enum DesignSource {
    Given(Design),
    Optimise(Box<ValidDesign>),
}

/// What a dynamic case asks for.
#[derive(Clone, Debug)]
pub enum DynamicsTask {
    /// A step response (forcing `step`) or a periodic response.
    Simulate,
    Damping {
        targets: Vec<f64>,
        settings: DampingSettings,
    },
    Periodic {
        delta_d: f64,
        method: SearchMethod,
        settings: PeriodicDesignSettings,
    },
}

/// A checked dynamic case.
#[derive(Clone, Debug)]
pub struct ValidDynamics {
    pub chain: Chain,
    pub design: DesignSource,
    pub damping: Vec<f64>,
    pub passive: NodalLoads,
    pub actuation: NodalLoads,
    pub forcing: Forcing,
    pub step: StepSettings,
    pub periodic: PeriodicSettings,
    pub task: DynamicsTask,
}

/// Most target rise times of eq. (35) in one case (one Ipopt solve each).
pub const MAX_TARGETS: usize = 100;
/// Most Ipopt iterations of one eq. (35) solve (each iteration simulates the step response).
pub const MAX_ITERATIONS: usize = 10_000;
/// Tightest Ipopt tolerance of eq. (35) (its constraint `T_90/T_d − 1` comes from an event
/// located to round-off on a simulated response; tighter is noise).
pub const MIN_TOLERANCE: f64 = 1e-14;

impl DynamicsCase {
    /// Checks the case for what `kind` asks of it.
    pub fn validate_for(&self, kind: DynamicKind) -> Result<ValidDynamics, CaseError> {
        let mut chain = self.chain.validate()?;
        let n = chain.n_links();
        if let Some(i) = chain.masses.iter().position(|m| *m <= 0.0) {
            return Err(CaseError::invalid(
                format!("chain.masses[{i}]"),
                format!("must be > 0 kg: every link of a dynamic case needs mass, got {}", chain.masses[i]),
            ));
        }
        let (passive, actuation) = self.loads.resolve(&mut chain)?;
        let design = self.design_source(&chain)?;
        let damping = self.damping.expand("damping", n + 1, "one per damper, N + 1")?;
        non_negative("damping", &damping, "N·m·s/rad")?;
        self.forcing.validate().map_err(|e| e.under("forcing"))?;

        let s = &self.simulation;
        check_simulation(s)?;
        s.integrator.check_reach(s.t_end, 2 * n).map_err(|e| CaseError::from(e.under("simulation.integrator")))?;
        check_periodic("periodic", &self.periodic)?;
        check_periodic_forcing("periodic", &self.forcing, &self.periodic, n)?;

        let task = match kind {
            DynamicKind::Simulate => self.simulate_task()?,
            DynamicKind::Damping => self.damping_task()?,
            DynamicKind::Periodic => self.periodic_task()?,
        };
        if let DynamicsTask::Periodic { delta_d, .. } = &task {
            crate::specs::check_reach("periodic_design.delta_d", *delta_d, chain.length_x())?;
        }
        Ok(ValidDynamics {
            chain,
            design,
            damping,
            passive,
            actuation,
            forcing: self.forcing.clone(),
            step: s.clone(),
            periodic: self.periodic.clone(),
            task,
        })
    }

    /// Where the design comes from: given, or eq. (33) run first on the `static_design` section
    /// (its errors named under `static_design`, except those of the shared chain and loads).
    fn design_source(&self, chain: &spine_model::Chain) -> Result<DesignSource, CaseError> {
        match (&self.design, &self.static_design) {
            (DesignSpec::Given(d), None) => Ok(DesignSource::Given(d.validate(chain)?)),
            (DesignSpec::Given(_), Some(_)) => Err(CaseError::invalid(
                "static_design",
                "only with \"design\": \"optimise\"; remove it or optimise the design",
            )),
            (DesignSpec::ToBeOptimised, None) => Err(CaseError::invalid(
                "static_design",
                "\"design\": \"optimise\" needs a static_design section (delta_d, start, …)",
            )),
            (DesignSpec::ToBeOptimised, Some(s)) => {
                let as_design = DesignCase {
                    title: self.title.clone(),
                    notes: Notes::default(),
                    chain: self.chain.clone(),
                    loads: self.loads.clone(),
                    delta_d: s.delta_d,
                    stiffness_scale: s.stiffness_scale,
                    bounds: s.bounds.clone(),
                    start: s.start.clone(),
                    objective: Default::default(),
                    constraints: Default::default(),
                    formulation: s.formulation,
                    multistart: MultiStartSpec::default(),
                    solver: s.solver.clone(),
                    preset: Default::default(),
                    fmincon_like_beside: false,
                    knife_edge: Default::default(),
                };
                let valid = as_design.validate().map_err(|e| match e.field() {
                    f if f.starts_with("chain") || f.starts_with("loads") => e,
                    _ => e.under("static_design"),
                })?;
                Ok(DesignSource::Optimise(Box::new(valid)))
            }
        }
    }

    /// Kind `simulate`: a force to respond to; a periodic force runs period by period, so the
    /// step section's own settings are refused rather than ignored.
    fn simulate_task(&self) -> Result<DynamicsTask, CaseError> {
        let s = &self.simulation;
        let periodic_forcing = self.forcing.period().is_some();
        if self.forcing == Forcing::Off {
            return Err(CaseError::invalid(
                "forcing.type",
                "a simulation needs a force: \"step\", \"pulse_train\" or \"sinusoid\"",
            ));
        }
        if periodic_forcing {
            let default = spine_dynamics::StepSettings::default();
            for (field, differs) in [
                ("simulation.t_end", s.t_end != default.t_end),
                ("simulation.samples", s.samples != default.samples),
                ("simulation", *s != default),
            ] {
                if differs {
                    return Err(CaseError::invalid(
                        field,
                        "a periodic forcing is simulated period by period until two agree: set periodic.max_periods, periodic.samples_per_period and periodic.integrator instead (the simulation section sets up step responses)",
                    ));
                }
            }
        }
        Ok(DynamicsTask::Simulate)
    }

    /// Kind `damping`: the eq. (35) section, checked.
    fn damping_task(&self) -> Result<DynamicsTask, CaseError> {
        let s = &self.simulation;
        let periodic_forcing = self.forcing.period().is_some();
        let Some(dd) = &self.damping_design else {
            return Err(CaseError::invalid(
                "damping_design",
                "a damping case needs a damping_design section with targets (s)",
            ));
        };
        // Eq. (35) always designs the step response; a periodic forcing is then applied to each
        // designed structure (the paper's Fig. 11).
        if !(self.forcing == Forcing::Step || periodic_forcing) {
            return Err(CaseError::invalid("forcing.type", "eq. (35) designs the step response: use \"step\", or a periodic force to simulate each design under afterwards"));
        }
        if dd.targets.is_empty() {
            return Err(CaseError::invalid("damping_design.targets", "give at least one target rise time (s)"));
        }
        if dd.targets.len() > MAX_TARGETS {
            return Err(CaseError::invalid(
                "damping_design.targets",
                format!("at most {MAX_TARGETS} targets (one eq. (35) solve each), got {}", dd.targets.len()),
            ));
        }
        for (i, t) in dd.targets.iter().enumerate() {
            let field = format!("damping_design.targets[{i}]");
            positive(&field, *t, "s")?;
            if let Some(j) = dd.targets[..i].iter().position(|u| u == t) {
                let message = format!("equal to targets[{j}] ({}); give each target once", spine_check::short(*t));
                return Err(CaseError::invalid(field, message));
            }
            if *t > MAX_T_END / 3.0 {
                let message = format!("at most {} s (each design simulates 3 T_d), got {t}", MAX_T_END / 3.0);
                return Err(CaseError::invalid(field, message));
            }
        }
        positive("damping_design.damping_min", dd.damping_min, "N·m·s/rad")?;
        if !(dd.damping_max.is_finite() && dd.damping_max > dd.damping_min) {
            return Err(CaseError::invalid(
                "damping_design.damping_max",
                format!("must be finite and > damping_min = {}, got {}", dd.damping_min, dd.damping_max),
            ));
        }
        if !(MIN_TOLERANCE..=1.0).contains(&dd.tolerance) {
            return Err(CaseError::invalid(
                "damping_design.tolerance",
                format!("Ipopt's tolerance: between {MIN_TOLERANCE:e} and 1, got {}", dd.tolerance),
            ));
        }
        if !(1..=MAX_ITERATIONS).contains(&dd.max_iterations) {
            return Err(CaseError::invalid(
                "damping_design.max_iterations",
                format!("must be between 1 and {MAX_ITERATIONS}, got {}", dd.max_iterations),
            ));
        }
        Ok(DynamicsTask::Damping {
            targets: dd.targets.clone(),
            settings: DampingSettings {
                damping_min: dd.damping_min,
                damping_max: dd.damping_max,
                tolerance: dd.tolerance,
                max_iterations: dd.max_iterations,
                step: s.clone(),
                overdamped: dd.overdamped,
            },
        })
    }

    /// Kind `periodic`: the eq. (37) section, checked.
    fn periodic_task(&self) -> Result<DynamicsTask, CaseError> {
        let periodic_forcing = self.forcing.period().is_some();
        let Some(pd) = &self.periodic_design else {
            return Err(CaseError::invalid(
                "periodic_design",
                "a periodic case needs a periodic_design section (delta_d, method)",
            ));
        };
        if !periodic_forcing {
            return Err(CaseError::invalid(
                "forcing.type",
                "eq. (37) needs a periodic force: \"pulse_train\" or \"sinusoid\"",
            ));
        }
        if !(pd.delta_d.is_finite() && pd.delta_d != 0.0) {
            return Err(CaseError::invalid(
                "periodic_design.delta_d",
                format!("must be a finite, nonzero displacement (m), got {}", pd.delta_d),
            ));
        }
        let st = &pd.settings;
        positive("periodic_design.settings.stiffness_min", st.stiffness_min, "N·m/rad")?;
        if !(st.stiffness_max.is_finite() && st.stiffness_max > st.stiffness_min) {
            return Err(CaseError::invalid(
                "periodic_design.settings.stiffness_max",
                format!("must be finite and > stiffness_min = {}, got {}", st.stiffness_min, st.stiffness_max),
            ));
        }
        positive("periodic_design.settings.tolerance", st.tolerance, "")?;
        st.ga.validate().map_err(|e| e.under("periodic_design.settings.ga"))?;
        st.pattern.validate().map_err(|e| e.under("periodic_design.settings.pattern"))?;
        st.gradient.validate().map_err(|e| e.under("periodic_design.settings.gradient"))?;
        if st.tolerance > 1.0 {
            return Err(CaseError::invalid(
                "periodic_design.settings.tolerance",
                format!("a relative band on |δ_d|: at most 1, got {}", st.tolerance),
            ));
        }
        check_periodic("periodic_design.settings.response", &st.response)?;
        check_periodic_forcing("periodic_design.settings.response", &self.forcing, &st.response, self.chain.links)?;
        Ok(DynamicsTask::Periodic { delta_d: pd.delta_d, method: pd.method, settings: st.clone() })
    }
}
