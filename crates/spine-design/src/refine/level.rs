//! One level of the ladder: its chain, start design and start states.

use super::mesh::{coarsen, prolong, restrict};
use crate::full_space::FullSpaceNlp;
use crate::layout::LoadState;
use crate::problem::DesignProblem;
use serde::{Deserialize, Serialize};
use spine_model::{Design, State};

/// How a level of the ladder started.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LevelStart {
    /// From the case's start design (restricted to the level), states by load continuation,
    /// Ipopt's default start options.
    Cold,
    /// Warm: prolonged coarser optimum,
    /// states by Newton at full load from the interpolated states.
    Newton,
    /// Warm, states by load continuation from the unloaded shape (Newton failed).
    Continuation,
    /// Warm, neither converged: the interpolated states themselves.
    Interpolated,
}

impl std::fmt::Display for LevelStart {
    /// As in result files: `cold`, `newton`, `continuation`, `interpolated`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(match self {
            Self::Cold => "cold",
            Self::Newton => "newton",
            Self::Continuation => "continuation",
            Self::Interpolated => "interpolated",
        })
    }
}

/// Exact equilibria of the prolonged design near the interpolated states, or the best fallback.
pub fn warm_states(
    problem: &DesignProblem,
    design: &Design,
    interpolated: (State, State),
    continuation: &spine_solve::ContinuationOptions,
) -> ((State, State), LevelStart) {
    if let Some(states) = problem.equilibria_near(design, &interpolated.0, &interpolated.1, continuation) {
        return (states, LevelStart::Newton);
    }
    let mut notes = Vec::new();
    let states = crate::problem::start_states(problem, design, continuation, &mut notes);
    if notes.is_empty() {
        (states, LevelStart::Continuation)
    } else {
        (interpolated, LevelStart::Interpolated)
    }
}

/// Scales every spring of a warm level's `design` by one factor `c` (each clamped to its bounds)
/// so that the loaded equilibrium's end displacement is `δ_d` again, the constraint the prolonged
/// design misses by a few millimetres; `states` follow (Newton at full load from the previous
/// ones). The secant method on `c`, from `c = δ(1)/δ_d` (a displacement inversely proportional to
/// the springs); at most `RESTORE_SOLVES` re-solves. Returns the violation `|X_{N+1}(θ2) − L_x −
/// δ_d|` (m) before and after, or `None` when nothing better was found (design and states
/// unchanged).
///
/// Why: the prolonged design satisfies every design constraint but this one (the coarse optimum
/// moves the fine chain's end by a few millimetres more or less), and from such a start with the
/// warm start's small `bound_push` Ipopt's first steps are short. Restored, the warm levels of the
/// scaled family take 30–65 % fewer iterations (docs/design.md, "Warm levels").
pub fn restore_end_displacement(
    problem: &DesignProblem,
    design: &mut Design,
    states: &mut (State, State),
    continuation: &spine_solve::ContinuationOptions,
) -> Option<[f64; 2]> {
    let spans = &problem.structure.chain.spans;
    let target = problem.structure.chain.length_x() + problem.delta_d;
    let residual =
        |d: &Design, loaded: &State| spine_model::kinematics::end_x(spans, &d.theta0, &loaded.theta) - target;
    let scaled = |c: f64| {
        let mut d = design.clone();
        for (j, k) in d.stiffness.iter_mut().enumerate() {
            *k = (*k * c).clamp(problem.bounds.stiffness_min[j], problem.bounds.stiffness_max[j]);
        }
        d
    };
    let r0 = residual(design, &states.1);
    let loads = problem.total_loads();
    // The secant iterates need the loaded state alone; the passive one follows for the best.
    let mut best: Option<(f64, Design, State)> = None;
    let (mut c_prev, mut r_prev) = (1.0, r0);
    let mut c = (r0 + problem.delta_d) / problem.delta_d;
    for _ in 0..RESTORE_SOLVES {
        if !(c.is_finite() && c > 0.0) {
            break;
        }
        let d = scaled(c);
        let Some(loaded) = problem.equilibrium_near(&d, loads.clone(), &states.1, continuation) else {
            break;
        };
        let r = residual(&d, &loaded);
        if best.as_ref().map_or(r0.abs(), |b| b.0.abs()) > r.abs() {
            best = Some((r, d, loaded));
        }
        if r.abs() <= RESTORED * problem.delta_d.abs() || r == r_prev {
            break;
        }
        let next = c - r * (c - c_prev) / (r - r_prev);
        (c_prev, r_prev, c) = (c, r, next);
    }
    let (r, d, loaded) = best?;
    let passive = problem.equilibrium_near(&d, problem.passive_loads(), &states.0, continuation)?;
    *design = d;
    *states = (passive, loaded);
    Some([r0.abs(), r.abs()])
}

/// Most equilibrium re-solves of [`restore_end_displacement`]: usually 2–4; a secant that starts
/// on the far side of a bound's kink takes 9 (the 20-link level of N = 100 from 10 links, seen
/// on Ipopt 3.14, where 8 ended at 2e-8 |δ_d|).
const RESTORE_SOLVES: usize = 16;
/// [`restore_end_displacement`] stops at this violation relative to `|δ_d|`.
const RESTORED: f64 = 1e-10;

/// One level of the ladder, ready for Ipopt: its chain (coarse, or the problem itself), how it
/// started, the start design and the start states.
pub struct LevelSetup {
    /// The coarse problem and the fine node of each coarse node; `None` at the problem's own `N`.
    pub coarse: Option<(DesignProblem, Vec<usize>)>,
    pub start: LevelStart,
    pub design: Design,
    pub states: (State, State),
    /// The end-displacement violation `|X_{N+1}(θ2) − L_x − δ_d|` (m) of the prolonged start
    /// before and after [`restore_end_displacement`], when it ran and improved it.
    pub restored: Option<[f64; 2]>,
}

impl LevelSetup {
    /// The level's problem: the coarse one, or `fine` itself.
    pub fn problem<'a>(&'a self, fine: &'a DesignProblem) -> &'a DesignProblem {
        self.coarse.as_ref().map_or(fine, |(c, _)| c)
    }
}

/// Prepares the level of `m` links of `problem`: cold from `start` restricted to it (states by
/// continuation, their notes added to `notes` with the level named) when there is no `previous`
/// level, else warm from the prolonged `previous` optimum (problem, design, states), with the
/// end displacement restored when `restore` ([`restore_end_displacement`]; not from merely
/// interpolated states).
#[allow(clippy::too_many_arguments)]
pub fn prepare_level(
    problem: &DesignProblem,
    m: usize,
    previous: Option<(&DesignProblem, &Design, &(State, State))>,
    start: &Design,
    restore: bool,
    continuation: &spine_solve::ContinuationOptions,
    notes: &mut Vec<String>,
) -> LevelSetup {
    let n = problem.n_links();
    let mut restored = None;
    let coarse = (m < n).then(|| coarsen(problem, m));
    let level = coarse.as_ref().map_or(problem, |(c, _)| c);
    let (how, design, states) = match previous {
        None => {
            let design = coarse.as_ref().map_or_else(|| start.clone(), |(c, nodes)| restrict(problem, c, nodes, start));
            let mut level_notes = Vec::new();
            let states = crate::problem::start_states(level, &design, continuation, &mut level_notes);
            notes.extend(level_notes.into_iter().map(|s| {
                if m < n {
                    format!("refinement level {m} links: {s}")
                } else {
                    s
                }
            }));
            (LevelStart::Cold, design, states)
        }
        Some((coarser, d, s)) => {
            let (mut design, interpolated) = prolong(coarser, level, d, s);
            let (mut states, how) = warm_states(level, &design, interpolated, continuation);
            if restore && how != LevelStart::Interpolated {
                restored = restore_end_displacement(level, &mut design, &mut states, continuation);
            }
            (how, design, states)
        }
    };
    LevelSetup { coarse, start: how, design, states, restored }
}

/// Design and states of a full-space solution vector.
pub fn solution_parts(nlp: &FullSpaceNlp<'_>, x: &[f64]) -> (Design, (State, State)) {
    let layout = nlp.layout;
    (
        layout.design(x, nlp.problem.stiffness_scale),
        (layout.state(x, LoadState::Passive), layout.state(x, LoadState::Loaded)),
    )
}

#[cfg(test)]
mod tests {
    use super::LevelStart;

    #[test]
    fn the_printed_level_start_is_its_serialised_name() {
        for s in [LevelStart::Cold, LevelStart::Newton, LevelStart::Continuation, LevelStart::Interpolated] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.to_string().as_str());
        }
    }
}
