//! One level of the ladder: its chain, start design and start states.

use super::mesh::{coarsen, prolong, restrict};
use crate::full_space::{FullSpaceNlp, LoadState};
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

/// One level of the ladder, ready for Ipopt: its chain (coarse, or the problem itself), how it
/// started, the start design and the start states.
pub struct LevelSetup {
    /// The coarse problem and the fine node of each coarse node; `None` at the problem's own `N`.
    pub coarse: Option<(DesignProblem, Vec<usize>)>,
    pub start: LevelStart,
    pub design: Design,
    pub states: (State, State),
}

impl LevelSetup {
    /// The level's problem: the coarse one, or `fine` itself.
    pub fn problem<'a>(&'a self, fine: &'a DesignProblem) -> &'a DesignProblem {
        self.coarse.as_ref().map_or(fine, |(c, _)| c)
    }
}

/// Prepares the level of `m` links of `problem`: cold from `start` restricted to it (states by
/// continuation, their notes added to `notes` with the level named) when there is no `previous`
/// level, else warm from the prolonged `previous` optimum (problem, design, states).
pub fn prepare_level(
    problem: &DesignProblem,
    m: usize,
    previous: Option<(&DesignProblem, &Design, &(State, State))>,
    start: &Design,
    continuation: &spine_solve::ContinuationOptions,
    notes: &mut Vec<String>,
) -> LevelSetup {
    let n = problem.n_links();
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
            let (design, interpolated) = prolong(coarser, level, d, s);
            let (states, how) = warm_states(level, &design, interpolated, continuation);
            (how, design, states)
        }
    };
    LevelSetup { coarse, start: how, design, states }
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
