//! The values runs compute, below every runner: a run inside a figure kept as a value
//! ([`RunOutput`]) that a recipe draws and checks, and the parts it holds (an eq. (33) run with
//! what the figures need, the design and output of a dynamic run, the two-link study's result).
//! Each kind says how it runs inside a figure ([`RunKind::in_figure`](crate::RunKind::in_figure)).

use serde::Serialize;
use spine_design::adjoint::ReducedGradients;
use spine_design::multistart::ConfidenceRun;
use spine_design::{DesignProblem, DesignResult};
use spine_dynamic_design::{DampingDesign, PeriodicDesign};
use spine_dynamics::{PeriodicResponse, StepResponse};
use spine_model::Design;
use spine_solve::twolink::Study;

/// What one run of a figure computed: for a two-link run the kind's own result; for eq. (33)
/// and the dynamics, the solver's state besides what `result.json` holds (the problem, the
/// projected start, the gradients, the whole trajectories) that a recipe draws and checks.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One value per run: boxing the two-link study as well would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum RunOutput {
    Twolink(TwoLinkResult),
    Design(Box<StaticDesign>),
    Dynamics { used: Box<UsedDesign>, output: DynamicOutput },
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
    /// With `multistart.confidence`: the best clean optimum of a census to that confidence, beside
    /// the optimum from the case's own start (the paper's), with the census that found it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best: Option<Box<BestDesign>>,
    /// How it was solved: "exact" or "fmincon-like" (the paper's kind of optimiser).
    pub preset: spine_design::SolverPreset,
    /// With `fmincon_like_beside`: the same case solved fmincon-like from the same start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fmincon_like: Option<Box<StaticDesign>>,
}

/// The best design of a census, as a figure draws it beside the paper-start optimum.
#[derive(Clone, Debug, Serialize)]
pub struct BestDesign {
    /// The best clean optimum, checked and certified, with its gradients (for the claims).
    pub design: StaticDesign,
    /// The start that reached it first (0: the case's own).
    pub reported_start: usize,
    /// Whether it is the optimum the case's own start reached.
    pub same_as_start: bool,
    /// Distinct optima found, the census estimate and how the census ran.
    pub optima: usize,
    pub census: spine_design::census::CensusEstimate,
    pub confidence: ConfidenceRun,
    /// The best optimum's mirror image (`θ0_i → −θ0_{N−1−i}`, `K_j → K_{N−j}`), when the census
    /// found it: a mirror-symmetric case's optima come in pairs of equal `J`, and which member
    /// leads the census depends on which start reached it first, so the claims are held to both
    /// (docs/findings.md, "Which conclusions survive at the best design?").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mirror_image: Option<StaticDesign>,
}

/// The design a dynamic run used: given, or from eq. (33) first.
#[derive(Clone, Debug, Serialize)]
pub struct UsedDesign {
    pub design: Design,
    /// Horizontal spans `a_i` of the chain, m (to draw its shapes).
    pub spans: Vec<f64>,
    pub static_design: Option<StaticDesign>,
}

/// What a dynamic run computed.
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
        design: Box<PeriodicDesign>,
    },
}

/// `result.json` of kind `twolink`.
#[derive(Clone, Debug, Serialize)]
pub struct TwoLinkResult {
    pub title: String,
    /// Link length `L`, m.
    pub length: f64,
    /// `K`, N·m/rad.
    pub stiffness: f64,
    /// Transverse load `P_Y` at the middle node and axial load `P_X` at the end, N.
    pub p_y: f64,
    pub p_x: f64,
    pub study: Study,
    pub total_seconds: f64,
}
