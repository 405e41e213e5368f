//! The values runs compute, below every runner: a run inside a figure kept as a value
//! ([`RunOutput`]) that a recipe draws and checks, and the parts it holds (an eq. (33) run with
//! what the figures need, the design and output of a dynamic run, the two-link study's result).
//! Each kind says how it runs inside a figure ([`RunKind::in_figure`](crate::RunKind::in_figure)).

use serde::Serialize;
use spine_design::adjoint::ReducedGradients;
use spine_design::knife_edge::KnifeEdge;
use spine_design::multistart::ConfidenceRun;
use spine_design::{DesignProblem, DesignResult};
use spine_dynamic_design::{DampingDesign, PeriodicDesign};
use spine_dynamics::{PeriodicResponse, StepResponse};
use spine_model::Design;
use spine_solve::twolink::Study;
use std::any::Any;

/// The value a kind's run gives inside a figure (its [`RunKind::in_figure`](crate::RunKind::in_figure)),
/// a type of the kind's own: a recipe asks for it by type ([`RunOutput::get`]), and it is written
/// in the figure's `result.json` under `runs[i].result`, tagged with [`InFigure::KIND`].
pub trait InFigure: Serialize + Clone + std::fmt::Debug + Send + Sync + 'static {
    /// `runs[i].result.kind` in the figure's `result.json`.
    const KIND: &'static str;
}

/// The object-safe side of [`InFigure`], what [`RunOutput`] holds.
trait Held: std::fmt::Debug + Send + Sync {
    fn kind(&self) -> &'static str;
    fn to_json(&self) -> Result<serde_json::Value, serde_json::Error>;
    fn clone_box(&self) -> Box<dyn Held>;
    fn as_any(&self) -> &dyn Any;
}

impl<T: InFigure> Held for T {
    fn kind(&self) -> &'static str {
        T::KIND
    }
    fn to_json(&self) -> Result<serde_json::Value, serde_json::Error> {
        serde_json::to_value(self)
    }
    fn clone_box(&self) -> Box<dyn Held> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// What one run of a figure computed, as its kind gives it ([`InFigure`]): for a two-link run the
/// kind's own result; for eq. (33) and the dynamics, the solver's state besides what `result.json`
/// holds (the problem, the projected start, the gradients, the whole trajectories) that a recipe
/// draws and checks. A kind a figure may hold needs no line here: its runner wraps its own type
/// ([`RunOutput::new`]) and the recipe that draws it asks for that type.
#[derive(Debug)]
pub struct RunOutput(Box<dyn Held>);

impl RunOutput {
    pub fn new<T: InFigure>(value: T) -> Self {
        Self(Box::new(value))
    }

    /// The run's value, where it is a `T` (`None` for a run of another kind).
    pub fn get<T: InFigure>(&self) -> Option<&T> {
        self.0.as_any().downcast_ref::<T>()
    }

    /// Its [`InFigure::KIND`].
    pub fn kind(&self) -> &'static str {
        self.0.kind()
    }
}

impl Clone for RunOutput {
    fn clone(&self) -> Self {
        Self(self.0.clone_box())
    }
}

impl Serialize for RunOutput {
    /// The value's own fields with `"kind"` ([`InFigure::KIND`]) beside them; a value that is not
    /// written as an object is put under `"value"`.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = match self.0.to_json().map_err(serde::ser::Error::custom)? {
            serde_json::Value::Object(map) => map,
            other => serde_json::Map::from_iter([("value".to_string(), other)]),
        };
        map.insert("kind".into(), self.kind().into());
        map.serialize(serializer)
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
    /// With `multistart.confidence`: the best clean optimum of a census to that confidence, beside
    /// the optimum from the case's own start (the paper's), with the census that found it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best: Option<Box<BestDesign>>,
    /// How it was solved: "exact" or "fmincon-like" (the paper's kind of optimiser).
    pub preset: spine_design::SolverPreset,
    /// With `fmincon_like_beside`: the same case solved fmincon-like from the same start.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fmincon_like: Option<Box<StaticDesign>>,
    /// With `knife_edge.pairs > 0`: the optima the start and its moved starts reached.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub knife_edge: Option<Box<KnifeEdgeDesigns>>,
}

/// A run's knife-edge check with each branch's design as the claims read it.
#[derive(Clone, Debug, Serialize)]
pub struct KnifeEdgeDesigns {
    #[serde(flatten)]
    pub edge: KnifeEdge,
    /// `edge.branches[b]`'s run (from its first start), with its gradients, in the same order.
    #[serde(skip)]
    pub designs: Vec<StaticDesign>,
    /// The first moved start that did not converge, where one did not.
    #[serde(skip)]
    pub failed: Option<StaticDesign>,
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

/// A dynamic run inside a figure: the design it used and what it computed (`"kind": "dynamics"`
/// for each of the three dynamic kinds).
#[derive(Clone, Debug, Serialize)]
pub struct DynamicsRun {
    pub used: UsedDesign,
    pub output: DynamicOutput,
}

impl InFigure for DynamicsRun {
    const KIND: &'static str = "dynamics";
}

impl InFigure for StaticDesign {
    const KIND: &'static str = "design";
}

impl InFigure for TwoLinkResult {
    const KIND: &'static str = "twolink";
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
