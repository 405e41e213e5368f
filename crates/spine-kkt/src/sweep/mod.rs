//! One frontal sweep (a stage of the analysis, or the root of a split) and the triangular solves
//! with its pivots.
//!
//! The sweep brings the variables into a dense front one at a time, in the stage's order; a
//! variable whose row is complete (fully summed) may be eliminated. Pivots are chosen among the
//! fully summed variables by the Bunch–Kaufman rule: a 1×1 pivot `p` when `|a_pp| ≥ α max_{i≠p}
//! |a_ip|` (α = (1 + √17)/8), else a 2×2 pivot with the row `r` of that largest entry. When `r`
//! is not fully summed yet, `p` is taken alone if `|a_pp| ≥ u max_i |a_ip|`, or with the fully
//! summed partner of largest coupling if that 2×2 block passes Duff and Reid's test with `u`;
//! otherwise it waits (a delayed pivot).
//!
//! * `u` is [`THRESHOLD`] (0.01) at first, [`RELAXED_THRESHOLD`] once the variable has waited
//!   [`PATIENCE`] steps and [`LAST_RESORT_THRESHOLD`] after four times as many: waiting widens the
//!   front, and a front as wide as the chain costs `O(N³)`.
//! * The dense rows (numbered first, fully summed only at the last step) take no part in the
//!   Bunch–Kaufman tests before the last step; a pivot must be at least [`BORDER_THRESHOLD`] of its
//!   entries in those rows until it has waited [`PATIENCE`] steps. Otherwise every variable whose
//!   largest entry lies in a dense row (in eq. (33): every angle, coupled to the slider row) would
//!   wait until the end.
//!
//! Ipopt factorises matrices of one structure hundreds of times, with values that change a little
//! from one to the next. Each sweep records its pivots (which, when, with which thresholds and
//! growth), and the next one replays them instead of searching: each pivot is tested again and
//! taken if its growth is within the threshold test or within twice what the search accepted
//! ([`crate::pivot::Growth::replays`]). Where one fails, the sweep searches as above until the
//! front holds again the variables the recorded sweep's held after the same step, then replays
//! again. In eq. (33)'s solves about 97 % of the pivots are replayed, and a replayed sweep takes
//! about 60 % of the time of a search.
//!
//! No pivot is perturbed, so the inertia of `D` is the inertia of `A` (Sylvester's law). A fully
//! summed column whose entries have all fallen below [`SINGULAR`] (in the scaled matrix) makes the
//! matrix singular.

mod eliminate;
mod replay;
mod solves;

use crate::analysis::{Analysis, Stage};
use crate::front::{Front, ABSENT};
use crate::pivot::{Growth, Thresholds, PATIENCE};
#[cfg(doc)]
use crate::pivot::{BORDER_THRESHOLD, LAST_RESORT_THRESHOLD, RELAXED_THRESHOLD, SINGULAR, THRESHOLD};
use crate::KktError;
use replay::{prepare_search, take_over};

/// The numbers of positive, negative and zero eigenvalues.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inertia {
    pub positive: usize,
    pub negative: usize,
    pub zero: usize,
}

/// Statistics of one factorisation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FactorStats {
    /// The widest front met.
    pub largest_front: usize,
    /// 2×2 pivots.
    pub two_by_two: usize,
    /// Times a fully summed variable had to wait for a later step.
    pub delayed: usize,
    /// Off-diagonal entries of `L`.
    pub factor_entries: usize,
    /// Pivots taken from the pivot sequence of the factorisation before (see [`crate::Factor::reusing`])
    /// without a search.
    pub replayed: usize,
    /// All pivots (1×1 and 2×2).
    pub pivots: usize,
    /// Passes of Ruiz's equilibration (three from `S = I`; from the scaling before, until it
    /// settles).
    pub scaling_passes: usize,
}

/// One pivot of `D`, with the range `start..end` of its rows in the factor's `index` and the
/// position `lower` of its first entry of `L`.
#[derive(Clone, Copy, Debug)]
enum Pivot {
    /// A 1×1 pivot on variable `p` (new numbering): `inverse = 1/d`.
    One { p: usize, inverse: f64, start: usize, end: usize, lower: usize },
    /// A 2×2 pivot on `p, r`: the inverse of the block, `[[i11, i12], [i12, i22]]`.
    Two { p: usize, r: usize, inverse: [[f64; 2]; 2], start: usize, end: usize, lower: usize },
}

/// The pivots of one sweep (a stage of the analysis, or the root of a split) and what it needs
/// to run again.
#[derive(Clone, Debug, Default)]
pub(crate) struct StageFactor {
    pivots: Vec<Pivot>,
    /// Row (new numbering) of each stored entry of `L`.
    index: Vec<usize>,
    /// Entries of `L`: one per index for a 1×1 pivot, two (columns p and r) for a 2×2 one.
    lower: Vec<f64>,
    pub(crate) inertia: Inertia,
    pub(crate) stats: FactorStats,
    /// The pivot sequence of this sweep, replayed by the next.
    pub(crate) schedule: Vec<Scheduled>,
    /// The sweep's storage, kept for the next factorisation.
    work: Workspace,
}

/// The working storage of a sweep, kept from one factorisation to the next: at N = 1000 it is
/// about 0.3 MB, which fresh pages would cost at every factorisation.
#[derive(Clone, Debug, Default)]
pub(crate) struct Workspace {
    front: Option<Front>,
    /// The step at which each variable became fully summed.
    since: Vec<usize>,
    waiting: Waiting,
    candidates: Vec<usize>,
    /// The step after which the recorded sweep had eliminated each variable.
    recorded_step: Vec<usize>,
    /// The storage of the schedule before the one replayed.
    spare_schedule: Vec<Scheduled>,
}

/// One pivot of a recorded sweep: the step after which it was taken, its variable(s) and the
/// thresholds it passed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Scheduled {
    step: usize,
    p: usize,
    r: Option<usize>,
    limits: Thresholds,
    growth: Growth,
}

/// Where a sweep is: its step, the border of the pivot tests there (the dense rows, or none at the
/// step that ends the factorisation), and whether it is that step.
#[derive(Clone, Copy, Debug)]
struct Step {
    index: usize,
    border: usize,
    last: bool,
}

/// The bookkeeping of the variables that wait: a waiting variable is tested again only when its
/// column, a fully summed partner's column or its threshold changed (skipping a test only delays a
/// pivot, which is always allowed).
#[derive(Clone, Debug, Default)]
struct Waiting {
    /// Whether the variable (new numbering) must be tested at its next chance.
    stale: Vec<bool>,
    /// The waiting period ([`Thresholds::after_waiting`]) of its last test.
    period: Vec<usize>,
    /// Per candidate, whether it was eliminated in this pass (scratch).
    gone: Vec<bool>,
}

impl StageFactor {
    /// The front the sweep left: after a half of a split, what goes to the root.
    pub(crate) fn front(&self) -> &Option<Front> {
        &self.work.front
    }

    /// Empties the stage's factor, then runs `sweep` with the pivot sequence recorded by the
    /// last run (to replay) and the stage's storage; the new sequence is written into the storage
    /// of the one before (no growth).
    pub(crate) fn run(
        &mut self,
        sweep: impl FnOnce(&mut Self, &[Scheduled], &mut Workspace) -> Result<(), KktError>,
    ) -> Result<(), KktError> {
        self.pivots.clear();
        self.index.clear();
        self.lower.clear();
        self.inertia = Inertia::default();
        self.stats = FactorStats::default();
        let mut work = std::mem::take(&mut self.work);
        let mut recorded = std::mem::replace(&mut self.schedule, std::mem::take(&mut work.spare_schedule));
        self.schedule.clear();
        let swept = sweep(self, &recorded, &mut work);
        recorded.clear();
        work.spare_schedule = recorded;
        self.work = work;
        self.stats.factor_entries = self.index.len();
        self.stats.pivots = self.pivots.len();
        swept
    }

    /// Brings the variable of step `t` into the front with the entries that enter with it; calls
    /// `on_entry(j)` for every variable `j` whose column changed.
    fn enter(
        stage: &Stage,
        t: usize,
        values: &[f64],
        scale: &[f64],
        front: &mut Front,
        mut on_entry: impl FnMut(usize),
    ) {
        let k = stage.vars[t];
        front.push(k);
        for &(j, e) in stage.entering(t) {
            let slot_j = front.slot_of[j];
            debug_assert_ne!(slot_j, ABSENT, "an entering entry's partner is still in the front");
            front.add_to_last(slot_j, values[e] * scale[j] * scale[k]);
            on_entry(j);
        }
    }

    /// The frontal sweep (see the module docs), recording its pivots in the schedule.
    ///
    /// Where `recorded` holds the pivots of an earlier sweep of a matrix of this structure, the
    /// sweep replays them, each tested again ([`Growth::replays`]), with no search. From the first
    /// one that fails, it searches; once the front holds again what the recorded sweep's held after
    /// the same step (a change of values usually changes a few pivots near one place of the chain),
    /// it goes back to replaying.
    pub(crate) fn sweep(
        &mut self,
        analysis: &Analysis,
        stage: &Stage,
        values: &[f64],
        scale: &[f64],
        recorded: &[Scheduled],
        work: &mut Workspace,
    ) -> Result<(), KktError> {
        let n = analysis.order();
        let steps = stage.len();
        // The step that ends the factorisation, if this stage's last one does.
        let last_step = if stage.ends { steps.checked_sub(1) } else { None };
        let front =
            work.front.get_or_insert_with(|| Front::new(n, analysis.predicted_front + 4, analysis.ordering.dense));
        front.clear(n, analysis.ordering.dense);
        let Workspace { since, waiting, candidates, recorded_step, .. } = work;
        // Every variable's `since` is set when it becomes fully summed, before it is read.
        since.resize(n, 0);
        // What only the search reads is set up when it first takes over (at the start, or where
        // a replayed pivot first fails: most replayed sweeps never search).
        waiting.stale.resize(n, true);
        let mut search_ready = false;
        let mut ready_search = |waiting: &mut Waiting, recorded_step: &mut Vec<usize>| {
            if !std::mem::replace(&mut search_ready, true) {
                prepare_search(n, recorded, waiting, recorded_step);
            }
        };
        candidates.clear();
        let (mut next, mut recorded_gone) = (0, 0);
        let mut replaying = !recorded.is_empty();
        if !replaying {
            ready_search(waiting, recorded_step);
        }
        for k in 0..steps {
            let stale = &mut waiting.stale;
            Self::enter(stage, k, values, scale, front, |j| stale[j] = true);
            for &v in stage.summed_at(k) {
                let slot_v = front.slot_of[v];
                front.mark_summed(slot_v);
                since[v] = k;
                if !replaying {
                    // A new fully summed partner may let a waiting variable pass.
                    for &w in candidates.iter() {
                        if front.at(front.slot_of[w], slot_v) != 0.0 {
                            waiting.stale[w] = true;
                        }
                    }
                    candidates.push(v);
                }
            }
            self.stats.largest_front = self.stats.largest_front.max(front.len());
            // Until the last step the dense rows (numbered first) stay out of the pivot tests: they
            // are summed only at the end, and a variable whose largest entry is in a dense row
            // would otherwise wait for it. The last step tests against every row.
            let last = last_step == Some(k);
            let border = if last { 0 } else { analysis.ordering.dense };
            if replaying {
                replaying = self.replay_step(front, recorded, (&mut next, &mut recorded_gone), k, border);
                if !replaying || (last && front.len() > 0) {
                    replaying = false;
                    ready_search(waiting, recorded_step);
                    take_over(front, candidates, &mut waiting.stale);
                }
            }
            if !replaying {
                let waited = |v: usize| (k - since[v]) / PATIENCE;
                self.eliminate_candidates(front, candidates, waiting, Step { index: k, border, last }, waited)?;
                self.stats.delayed += candidates.len();
                while let Some(pivot) = recorded.get(next).filter(|pivot| pivot.step <= k) {
                    next += 1;
                    recorded_gone += 1 + usize::from(pivot.r.is_some());
                }
                // Back in step with the recorded sweep: the same variables left in the front.
                let in_step = next < recorded.len()
                    && front.len() + recorded_gone == k + 1
                    && front.var.iter().all(|&v| recorded_step[v] > k);
                if in_step {
                    replaying = true;
                    candidates.clear();
                }
            }
        }
        debug_assert!(!stage.ends || front.len() == 0, "the last step eliminates every variable");
        Ok(())
    }

    /// The root of a split: the fronts the two halves left (the dense rows, the variables coupled
    /// across the cut, and any pivots they delayed) summed into one, the entries across the cut
    /// entered, and everything eliminated as at a sweep's last step (the recorded pivots replayed
    /// while they pass, the rest searched).
    pub(crate) fn root(
        &mut self,
        analysis: &Analysis,
        halves: [&Option<Front>; 2],
        values: &[f64],
        scale: &[f64],
        recorded: &[Scheduled],
        work: &mut Workspace,
    ) -> Result<(), KktError> {
        let (n, dense) = (analysis.order(), analysis.ordering.dense);
        let width = halves.iter().map(|half| half.as_ref().map_or(0, Front::len)).sum::<usize>();
        let front = work.front.get_or_insert_with(|| Front::new(n, width + 4, dense));
        front.clear(n, dense);
        for half in halves.into_iter().flatten() {
            front.absorb(half);
        }
        for &(i, j, e) in &analysis.crossing {
            let (slot_i, slot_j) = (front.slot_of[i], front.slot_of[j]);
            debug_assert!(slot_i != ABSENT && slot_j != ABSENT, "an entry across the cut joins two root variables");
            front.add(slot_i, slot_j, values[e] * scale[i] * scale[j]);
        }
        for slot in 0..front.len() {
            front.mark_summed(slot);
        }
        self.stats.largest_front = front.len();
        for &pivot in recorded {
            if !self.replay(front, pivot, 0) {
                break;
            }
        }
        if front.len() > 0 {
            let Workspace { waiting, candidates, .. } = work;
            // Sized for the tests; at the root, as at a sweep's last step, every candidate is
            // tested on every pass whatever its marks.
            waiting.stale.resize(n, true);
            waiting.period.resize(n, 0);
            take_over(front, candidates, &mut waiting.stale);
            self.eliminate_candidates(front, candidates, waiting, Step { index: 0, border: 0, last: true }, |_| 0)?;
            self.stats.delayed += candidates.len();
        }
        debug_assert_eq!(front.len(), 0, "the root eliminates every variable");
        Ok(())
    }
}
