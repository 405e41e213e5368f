//! Kinds `simulate`, `damping` and `periodic`: the dynamics of Sec. 5.2 on a given design or on
//! the eq. (33) design of the case.

use crate::animation::{Animation, AnimationOptions, Track};
use crate::design::run_design;
use crate::error::RunError;
use crate::files::{samples_table, FileContent, OutputFile};
use crate::output::{DynamicOutput, DynamicsRun, RunOutput, UsedDesign};
use crate::progress::Progress;
use serde::{Serialize, Serializer};
use spine_case::{DampingCase, DesignSource, DynamicKind, DynamicsTask, PeriodicCase, SimulateCase, ValidDynamics};
use spine_dynamic_design::{design_damping, design_periodic, DampingDesign, PeriodicDesign, SearchMethod};
use spine_dynamics::{periodic_response, step_response, DynamicProblem, Forcing, PeriodicResponse, StepResponse};
use spine_model::{Design, Structure};

/// The design of a dynamic case: given, or found by eq. (33) first, which must end clean.
pub fn resolve_design(valid: &ValidDynamics) -> Result<UsedDesign, RunError> {
    let used = design_of(valid)?;
    if let Some(s) = used.static_design.as_ref().filter(|s| !s.result.is_clean()) {
        return Err(RunError::StaticDesignNotClean {
            status: s.result.solver.status,
            warnings: s.result.warnings.iter().map(ToString::to_string).collect(),
        });
    }
    Ok(used)
}

/// The design of a dynamic case, given or from eq. (33), clean or not.
fn design_of(valid: &ValidDynamics) -> Result<UsedDesign, RunError> {
    match &valid.design {
        DesignSource::Given(d) => {
            Ok(UsedDesign { design: d.clone(), spans: valid.chain.spans.clone(), static_design: None })
        }
        DesignSource::Optimise(v) => {
            let s = run_design(v, None)?;
            Ok(UsedDesign { design: s.result.design.clone(), spans: valid.chain.spans.clone(), static_design: Some(s) })
        }
    }
}

/// The dynamic problem of a case with a resolved design and the given dampers.
pub fn dynamic_problem(valid: &ValidDynamics, design: &Design, damping: &[f64]) -> DynamicProblem {
    let structure =
        Structure { chain: valid.chain.clone(), passive: valid.passive.clone(), actuation: valid.actuation.clone() };
    DynamicProblem { structure, design: design.clone(), damping: damping.to_vec() }
}

/// Runs a dynamic case: its design (which must end clean), then its task.
pub fn run_dynamics(
    valid: &ValidDynamics,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<(UsedDesign, DynamicOutput), RunError> {
    let used = resolve_design(valid)?;
    let output = run_task(valid, &used, progress)?;
    Ok((used, output))
}

/// The task of a dynamic case on its resolved design.
fn run_task(
    valid: &ValidDynamics,
    used: &UsedDesign,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<DynamicOutput, RunError> {
    let problem = dynamic_problem(valid, &used.design, &valid.damping);
    let periodic = |damping: &[f64]| {
        periodic_response(&dynamic_problem(valid, &used.design, damping), valid.forcing.clone(), None, &valid.periodic)
    };
    let output = match &valid.task {
        DynamicsTask::Simulate if valid.forcing.period().is_none() => {
            DynamicOutput::Step { response: step_response(&problem, &valid.step, false).map_err(RunError::Dynamics)? }
        }
        DynamicsTask::Simulate => {
            DynamicOutput::Periodic { response: periodic(&valid.damping).map_err(RunError::Dynamics)? }
        }
        DynamicsTask::Damping { targets, settings } => {
            let mut designs = Vec::new();
            let mut responses = Vec::new();
            for (k, &target) in targets.iter().enumerate() {
                progress(Progress::Step { stage: "eq. (35)", done: k, total: targets.len() });
                let d = design_damping(&problem, target, settings).map_err(RunError::DynamicDesign)?;
                if valid.forcing.period().is_some() {
                    responses.push(periodic(&d.damping).map_err(RunError::Dynamics)?);
                }
                designs.push(d);
            }
            progress(Progress::Step { stage: "eq. (35)", done: targets.len(), total: targets.len() });
            DynamicOutput::Damping { designs, periodic: responses }
        }
        DynamicsTask::Periodic { delta_d, method, settings } => {
            let (stage, total) = match method {
                SearchMethod::Ga => ("eq. (37) Ga", settings.ga.generations),
                SearchMethod::Pattern => ("eq. (37) Pattern", settings.pattern.max_evaluations),
                SearchMethod::Gradient => ("eq. (37) Gradient", settings.gradient.max_iterations),
            };
            let design = design_periodic(&problem, valid.forcing.clone(), *delta_d, *method, settings, &mut |p| {
                let done = match method {
                    SearchMethod::Ga | SearchMethod::Gradient => p.iteration,
                    SearchMethod::Pattern => p.evaluations,
                };
                progress(Progress::Step { stage, done, total })
            })
            .map_err(RunError::DynamicDesign)?;
            DynamicOutput::PeriodicDesign { design: Box::new(design) }
        }
    };
    Ok(output)
}

/// Where the design of a dynamic case came from: `"given"`, or a summary of its eq. (33) run.
#[derive(Clone, Debug)]
pub enum DesignOrigin {
    Given,
    Eq33(Eq33Summary),
}

/// The eq. (33) run a dynamic case's design came from.
#[derive(Clone, Debug, Serialize)]
pub struct Eq33Summary {
    pub source: &'static str,
    pub status: spine_ipopt::Status,
    pub iterations: usize,
    /// `J`, J.
    pub objective: f64,
    /// `X(θ2) − L_x` and its target, m.
    pub end_displacement: Option<f64>,
    pub delta_d: f64,
    /// The design ended clean; when not, no dynamics ran on it and `warnings` say why.
    pub clean: bool,
    pub warnings: Vec<String>,
}

impl Serialize for DesignOrigin {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Given => s.serialize_str("given"),
            Self::Eq33(summary) => summary.serialize(s),
        }
    }
}

/// The design of a dynamic result.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicsDesign {
    /// `θ0`, rad.
    pub theta0: Vec<f64>,
    /// `K`, N·m/rad.
    pub stiffness: Vec<f64>,
    pub source: DesignOrigin,
}

/// One eq. (35) design, with its response to the case's periodic forcing (if any).
#[derive(Clone, Debug, Serialize)]
pub struct DampingRun {
    #[serde(flatten)]
    pub design: DampingDesign,
    pub periodic_response: Option<PeriodicResponse>,
}

/// `result.json` of kinds `simulate`, `damping` and `periodic`: one of the four task fields is set.
#[derive(Clone, Debug, Serialize)]
pub struct DynamicsResult {
    pub title: String,
    pub design: DynamicsDesign,
    /// Dampers `C_i` of the case, N·m·s/rad.
    pub damping: Vec<f64>,
    pub forcing: Forcing,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_response: Option<StepResponse>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periodic_response: Option<PeriodicResponse>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damping_designs: Option<Vec<DampingRun>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periodic_design: Option<PeriodicDesign>,
    /// `T_90` is reported as `T_{100·rise_fraction}`.
    #[serde(skip)]
    pub rise_fraction: f64,
    #[serde(skip)]
    pub n_links: usize,
    /// The chain's motion, written as `animation.gif` when asked for.
    #[serde(skip)]
    pub animation: Option<Animation>,
}

/// Runs a dynamic case of kind `kind` with title `title`, with an animation of its responses
/// when `animation` is set.
pub fn run_dynamics_case(
    kind: DynamicKind,
    title: &str,
    valid: &ValidDynamics,
    animation: Option<AnimationOptions>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<DynamicsResult, RunError> {
    // A design from eq. (33) that did not end clean is reported (exit 3), with no dynamics on it.
    let used = design_of(valid)?;
    let clean_design = used.static_design.as_ref().is_none_or(|s| s.result.is_clean());
    let output = if clean_design { Some(run_task(valid, &used, progress)?) } else { None };
    let source = match &used.static_design {
        None => DesignOrigin::Given,
        Some(s) => DesignOrigin::Eq33(Eq33Summary {
            source: "eq. (33)",
            status: s.result.solver.status,
            iterations: s.result.solver.iterations,
            objective: s.result.objective,
            end_displacement: s.result.end_displacement,
            delta_d: s.result.delta_d,
            clean: s.result.is_clean(),
            warnings: s.result.warnings.iter().map(ToString::to_string).collect(),
        }),
    };
    let mut result = DynamicsResult {
        title: if title.is_empty() { kind.name().to_string() } else { title.to_string() },
        design: DynamicsDesign { theta0: used.design.theta0.clone(), stiffness: used.design.stiffness.clone(), source },
        damping: valid.damping.clone(),
        forcing: valid.forcing.clone(),
        step_response: None,
        periodic_response: None,
        damping_designs: None,
        periodic_design: None,
        rise_fraction: valid.step.rise_fraction,
        n_links: valid.chain.n_links(),
        animation: None,
    };
    match output {
        None => {}
        Some(DynamicOutput::Step { response }) => result.step_response = Some(response),
        Some(DynamicOutput::Periodic { response }) => result.periodic_response = Some(response),
        Some(DynamicOutput::Damping { designs, periodic }) => {
            let mut periodic = periodic.into_iter();
            result.damping_designs = Some(
                designs.into_iter().map(|design| DampingRun { design, periodic_response: periodic.next() }).collect(),
            );
        }
        Some(DynamicOutput::PeriodicDesign { design }) => result.periodic_design = Some(*design),
    }
    if let Some(options) = animation {
        let tracks = result.tracks(&valid.chain.spans);
        result.animation = (!tracks.is_empty()).then(|| Animation { title: result.title.clone(), tracks, options });
    }
    Ok(result)
}

impl DynamicsResult {
    /// The responses to animate: the step or periodic response, each eq. (35) design's step
    /// response, or the eq. (37) design's periodic response.
    fn tracks(&self, spans: &[f64]) -> Vec<Track> {
        let track = |label: String, samples| Track::new(label, spans, &self.design.theta0, samples);
        let mut tracks = Vec::new();
        if let Some(r) = &self.step_response {
            tracks.push(track("step response".into(), &r.samples));
        }
        if let Some(r) = &self.periodic_response {
            tracks.push(track("periodic response".into(), &r.samples));
        }
        for d in self.damping_designs.iter().flatten() {
            tracks.push(track(format!("T_d = {} s", d.design.target_rise_time), &d.design.response.samples));
        }
        if let Some(r) = &self.periodic_design {
            tracks.push(track("eq. (37) design".into(), &r.response.samples));
        }
        tracks
    }
}

/// The runners of the three dynamic kinds: one case format ([`spine_case::DynamicsCase`]) that
/// its type checks for its task.
macro_rules! dynamic_runners {
    ($($case:ty),+) => {$(
        impl crate::RunKind for $case {
            type Output = DynamicsResult;
            const MOVES: bool = true;
            const IN_FIGURE: bool = true;

            fn run(&self, cx: &mut crate::RunContext<'_>) -> Result<DynamicsResult, RunError> {
                let mut valid = self.validate()?;
                cx.overrides.dynamics.apply(&mut valid);
                run_dynamics_case(Self::KIND, &self.title, &valid, cx.overrides.animation, cx.progress)
            }

            fn in_figure(
                &self,
                _: Option<&crate::workers::Workers>,
                progress: &mut dyn FnMut(Progress<'_>),
            ) -> Option<Result<RunOutput, RunError>> {
                Some(self.validate().map_err(RunError::from).and_then(|valid| {
                    let (used, output) = run_dynamics(&valid, progress)?;
                    Ok(RunOutput::new(DynamicsRun { used, output }))
                }))
            }
        }
    )+};
}

dynamic_runners!(SimulateCase, DampingCase, PeriodicCase);

impl crate::KindOutput for DynamicsResult {
    /// Step: settled in θ2 with a rise time; periodic: settled; eq. (35): every design converged
    /// within [`spine_dynamic_design::RISE_TIME_ACCEPTANCE`] of its target (and its periodic response
    /// settled); eq. (37): feasible and settled.
    fn is_clean(&self) -> bool {
        if let Some(r) = &self.step_response {
            return r.settled && r.rise_time.is_some();
        }
        if let Some(r) = &self.periodic_response {
            return r.is_meaningful();
        }
        if let Some(designs) = &self.damping_designs {
            return designs
                .iter()
                .all(|d| d.design.meets_target() && d.periodic_response.as_ref().is_none_or(|p| p.is_meaningful()));
        }
        self.periodic_design.as_ref().is_some_and(|r| r.feasible && r.finished() && r.response.is_meaningful())
    }

    /// The periodic responses whose numbers mean nothing, with why (the forcing period to blame
    /// when the swing is below the integrator's resolution).
    fn not_clean_reasons(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(reason) = self.periodic_response.as_ref().and_then(|r| r.not_meaningful_reason()) {
            out.push(format!("periodic response: {reason}"));
        }
        for d in self.damping_designs.iter().flatten() {
            if let Some(reason) = d.periodic_response.as_ref().and_then(|r| r.not_meaningful_reason()) {
                out.push(format!("T_d = {} s, periodic response: {reason}", d.design.target_rise_time));
            }
        }
        if let Some(reason) = self.periodic_design.as_ref().and_then(|r| r.response.not_meaningful_reason()) {
            out.push(format!("eq. (37) design, periodic response: {reason}"));
        }
        out
    }

    /// `response.csv` (step, periodic, eq. (37)), or `response_T{T_d}.csv` and
    /// `periodic_T{T_d}.csv` for each eq. (35) target.
    fn files(&self) -> Vec<OutputFile> {
        let csv = |name: String, samples| OutputFile::table(name, samples_table(samples));
        let mut files = Vec::new();
        if let Some(r) = &self.step_response {
            files.push(csv("response.csv".into(), &r.samples));
        }
        if let Some(r) = &self.periodic_response {
            files.push(csv("response.csv".into(), &r.samples));
        }
        // A target's name in short form (`0.2`, `1e-300`), or in full where two targets share it.
        let targets: Vec<f64> = self.damping_designs.iter().flatten().map(|d| d.design.target_rise_time).collect();
        let name = |t: f64| {
            let short = spine_check::short(t);
            let shared = targets.iter().filter(|&&u| spine_check::short(u) == short).count() > 1;
            if shared {
                format!("{t:e}")
            } else {
                short
            }
        };
        for d in self.damping_designs.iter().flatten() {
            let target = name(d.design.target_rise_time);
            files.push(csv(format!("response_T{target}.csv"), &d.design.response.samples));
            if let Some(p) = &d.periodic_response {
                files.push(csv(format!("periodic_T{target}.csv"), &p.samples));
            }
        }
        if let Some(r) = &self.periodic_design {
            files.push(csv("response.csv".into(), &r.response.samples));
        }
        if let Some(a) = &self.animation {
            files.push(OutputFile { name: "animation".into(), content: FileContent::Animation(a.clone()) });
        }
        files
    }
}
