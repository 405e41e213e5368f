//! The numerical factorisation `P S A S Pᵀ = L D Lᵀ` by a frontal sweep (Pardiso's phase 22), and
//! solves with it.
//!
//! `S` is a diagonal equilibration (a few passes of Ruiz's scaling, so that every row of `S A S`
//! has largest entry about 1), `P` the order of [`Analysis`]. The sweep brings the variables into a
//! dense front one at a time, in that order; a variable whose row is complete (fully summed) may be
//! eliminated. Pivots are chosen among the fully summed variables by the Bunch–Kaufman rule: a
//! 1×1 pivot `p` when `|a_pp| ≥ α max_{i≠p} |a_ip|` (α = (1 + √17)/8), else a 2×2 pivot with the
//! row `r` of that largest entry. When `r` is not fully summed yet, `p` is taken alone if
//! `|a_pp| ≥ u max_i |a_ip|`, or with the fully summed partner of largest coupling if that 2×2
//! block passes Duff and Reid's test with `u`; otherwise it waits (a delayed pivot).
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
//! from one to the next. Each factorisation records its pivots (which, when, with which
//! thresholds and growth), and the next one replays them instead of searching: each pivot is
//! tested again and taken if its growth is within the threshold test or within twice what the
//! search accepted ([`crate::pivot::Growth::replays`]). Where one fails, the sweep searches as
//! above until the front holds again the variables the recorded sweep's held after the same step,
//! then replays again. In eq. (33)'s solves about 97 % of the pivots are replayed, and a replayed
//! sweep takes about 60 % of the time of a search.
//!
//! No pivot is perturbed, so the inertia of `D` is the inertia of `A` (Sylvester's law). A fully
//! summed column whose entries have all fallen below [`SINGULAR`] (in the scaled matrix) makes the
//! matrix singular. The relaxed thresholds allow growth; the solver's iterative refinement and, where
//! that stalls, one GMRES correction ([`crate::SymmetricSolver::solve`]) repair the solution.

use crate::analysis::{Analysis, Stage};
use crate::front::{Front, ABSENT};
use crate::pivot::{choose, growth, Choice, Growth, Thresholds};
pub use crate::pivot::{BORDER_THRESHOLD, LAST_RESORT_THRESHOLD, PATIENCE, RELAXED_THRESHOLD, SINGULAR, THRESHOLD};
use crate::KktError;

/// Passes of Ruiz's equilibration from `S = I`.
const SCALING_PASSES: usize = 3;
/// From the scaling of the factorisation before (Ipopt's matrices change a little from one
/// factorisation to the next, so it is a close start), Ruiz's passes stop once a pass has changed
/// no scale factor by more than this factor (at most [`SCALING_PASSES`] passes). In eq. (33)'s
/// solves (N = 200, 1000) half the factorisations take one pass and a twentieth three, 1.6 on
/// average; a pass takes about 0.1 ms at N = 1000 (a fourteenth of a replayed factorisation).
const SCALING_SETTLED: f64 = 10.0;

/// The numbers of positive, negative and zero eigenvalues.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inertia {
    pub positive: usize,
    pub negative: usize,
    pub zero: usize,
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
    /// Pivots taken from the pivot sequence of the factorisation before (see [`Factor::reusing`])
    /// without a search.
    pub replayed: usize,
    /// All pivots (1×1 and 2×2).
    pub pivots: usize,
    /// Passes of Ruiz's equilibration ([`SCALING_PASSES`] from `S = I`; from the scaling before,
    /// until it settles).
    pub scaling_passes: usize,
}

/// `L`, `D`, the scaling and the order: everything a solve needs.
#[derive(Clone, Debug)]
pub struct Factor {
    order: Vec<usize>,
    /// `S` in the new numbering.
    scale: Vec<f64>,
    /// `S` in the original numbering (the next factorisation's start).
    original_scale: Vec<f64>,
    /// One per stage of the analysis, and after a split the root's: the pivots of one sweep.
    stages: Vec<StageFactor>,
    inertia: Inertia,
    stats: FactorStats,
}

/// The pivots of one sweep (a stage of the analysis, or the root of a split) and what it needs
/// to run again.
#[derive(Clone, Debug, Default)]
struct StageFactor {
    pivots: Vec<Pivot>,
    /// Row (new numbering) of each stored entry of `L`.
    index: Vec<usize>,
    /// Entries of `L`: one per index for a 1×1 pivot, two (columns p and r) for a 2×2 one.
    lower: Vec<f64>,
    inertia: Inertia,
    stats: FactorStats,
    /// The pivot sequence of this sweep, replayed by the next.
    schedule: Vec<Scheduled>,
    /// The sweep's storage, kept for the next factorisation.
    work: Workspace,
}

/// The working storage of a sweep, kept from one factorisation to the next: at N = 1000 it is
/// about 0.3 MB, which fresh pages would cost at every factorisation.
#[derive(Clone, Debug, Default)]
struct Workspace {
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
struct Scheduled {
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

/// Ruiz's equilibration of the symmetric matrix: `s` (original numbering) with the largest entry of
/// every nonzero row of `S A S` close to 1, by [`SCALING_PASSES`] passes from `s`, or fewer when
/// `until_settled` and a pass has changed no factor by more than [`SCALING_SETTLED`].
fn equilibrate(analysis: &Analysis, values: &[f64], mut s: Vec<f64>, until_settled: bool) -> (Vec<f64>, usize) {
    let n = analysis.order();
    let mut largest = vec![0.0f64; n];
    let mut passes = 0;
    while passes < SCALING_PASSES {
        passes += 1;
        largest.fill(0.0);
        // Row by row, row `r`'s largest kept in a register (the values are finite, so a plain
        // comparison is `f64::max`; the largest of a set does not depend on the order).
        for r in 0..n {
            let (positions, columns) = analysis.structure.row(r);
            let (sr, mut lr) = (s[r], largest[r]);
            for (e, &c) in positions.zip(columns) {
                let v = (values[e] * sr * s[c]).abs();
                lr = if v > lr { v } else { lr };
                // Branch-free; on the diagonal (c = r) harmless, as `lr` holds it too.
                let lc = largest[c];
                largest[c] = if v > lc { v } else { lc };
            }
            largest[r] = lr;
        }
        let (mut least, mut most) = (1.0f64, 1.0f64);
        for (si, &m) in s.iter_mut().zip(&largest) {
            // Branch-free (so that it vectorises): rows without a finite nonzero keep their scale.
            let m = if m > 0.0 && m.is_finite() { m } else { 1.0 };
            (least, most) = (least.min(m), most.max(m));
            *si /= m.sqrt();
        }
        let settled = SCALING_SETTLED * SCALING_SETTLED;
        if until_settled && most <= settled && least >= 1.0 / settled {
            break;
        }
    }
    (s, passes)
}

impl Factor {
    /// Factorises the matrix with these values (in the order of the analysed structure).
    pub fn new(analysis: &Analysis, values: &[f64]) -> Result<Self, KktError> {
        Self::reusing(analysis, values, None, false)
    }

    /// [`Factor::new`], writing into the storage of an earlier factorisation (Ipopt factorises
    /// matrices of one structure hundreds of times; at N = 1000 `L` takes about 2 MB, and fresh
    /// pages cost a tenth of the factorisation).
    /// With `two_threads`, the two halves of a split sweep at once (the factor is the same to the
    /// bit either way).
    pub fn reusing(
        analysis: &Analysis,
        values: &[f64],
        old: Option<Factor>,
        two_threads: bool,
    ) -> Result<Self, KktError> {
        let n = analysis.order();
        if values.len() != analysis.structure.stored() {
            return Err(KktError::Input(format!(
                "{} values for a structure of {} entries",
                values.len(),
                analysis.structure.stored()
            )));
        }
        if let Some(e) = values.iter().position(|v| !v.is_finite()) {
            return Err(KktError::Input(format!("value {e} is not finite")));
        }
        // The factorisation before, when it was of this order, gives the scaling's start and the
        // pivot sequence to replay.
        let mut old = old;
        let same_order = old.as_ref().is_some_and(|f| f.order == analysis.ordering.order);
        let previous = old.as_mut().filter(|_| same_order).map(|f| std::mem::take(&mut f.original_scale));
        let (s, passes) = match previous {
            Some(start) => equilibrate(analysis, values, start, true),
            None => equilibrate(analysis, values, vec![1.0; n], false),
        };
        let mut factor = old.unwrap_or_else(|| Factor {
            order: Vec::with_capacity(n),
            scale: Vec::with_capacity(n),
            original_scale: Vec::new(),
            stages: Vec::new(),
            inertia: Inertia::default(),
            stats: FactorStats::default(),
        });
        // Pivot sequences recorded on another order cannot be replayed.
        if !same_order {
            factor.stages.clear();
        }
        factor.stages.resize_with(analysis.stages.len() + usize::from(analysis.is_split()), StageFactor::default);
        factor.reset(analysis, &s, same_order);
        factor.original_scale = s;
        let swept = factor.sweep_stages(analysis, values, two_threads);
        for stage in &factor.stages {
            let (sum, part) = (&mut factor.stats, stage.stats);
            sum.largest_front = sum.largest_front.max(part.largest_front);
            sum.two_by_two += part.two_by_two;
            sum.delayed += part.delayed;
            sum.factor_entries += part.factor_entries;
            sum.replayed += part.replayed;
            sum.pivots += part.pivots;
            factor.inertia.positive += stage.inertia.positive;
            factor.inertia.negative += stage.inertia.negative;
        }
        factor.stats.scaling_passes = passes;
        swept.map(|()| factor)
    }

    /// Empties the factor and sets the order and scaling for a new sweep.
    fn reset(&mut self, analysis: &Analysis, s: &[f64], same_order: bool) {
        if !same_order {
            self.order.clear();
            self.order.extend_from_slice(&analysis.ordering.order);
        }
        self.scale.clear();
        self.inertia = Inertia::default();
        self.stats = FactorStats::default();
        self.scale.extend(analysis.ordering.order.iter().map(|&v| s[v]));
    }

    /// Runs the stages: one sweep; or the two halves of a split (on two threads with
    /// `two_threads`), then the root.
    fn sweep_stages(&mut self, analysis: &Analysis, values: &[f64], two_threads: bool) -> Result<(), KktError> {
        let scale = &self.scale;
        let sweep = |factor: &mut StageFactor, s: usize| {
            factor.run(|f, recorded, work| f.sweep(analysis, &analysis.stages[s], values, scale, recorded, work))
        };
        match self.stages.as_mut_slice() {
            [single] => sweep(single, 0),
            [first, second, root] => {
                let (one, two) = if two_threads {
                    std::thread::scope(|scope| {
                        let one = scope.spawn(|| sweep(first, 0));
                        let two = sweep(second, 1);
                        // A panic of the first half's thread goes on in this one.
                        (one.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)), two)
                    })
                } else {
                    (sweep(first, 0), sweep(second, 1))
                };
                one?;
                two?;
                let halves = [&first.work.front, &second.work.front];
                root.run(|f, recorded, work| f.root(analysis, halves, values, scale, recorded, work))
            }
            _ => Err(KktError::Input(format!(
                "{} stages for an analysis of {}",
                self.stages.len(),
                analysis.stages.len()
            ))),
        }
    }
}

impl StageFactor {
    /// Empties the stage's factor, then runs `sweep` with the pivot sequence recorded by the
    /// last run (to replay) and the stage's storage; the new sequence is written into the storage
    /// of the one before (no growth).
    fn run(
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
    fn sweep(
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
            if std::mem::replace(&mut search_ready, true) {
                return;
            }
            waiting.stale.fill(true);
            waiting.period.clear();
            waiting.period.resize(n, 0);
            // The step after which the recorded sweep had eliminated each variable (`n`: never).
            recorded_step.clear();
            recorded_step.resize(if recorded.is_empty() { 0 } else { n }, n);
            for pivot in recorded {
                recorded_step[pivot.p] = pivot.step;
                if let Some(r) = pivot.r {
                    recorded_step[r] = pivot.step;
                }
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
                while let Some(&pivot) = recorded.get(next).filter(|pivot| pivot.step == k) {
                    if !self.replay(front, pivot, border) {
                        replaying = false;
                        break;
                    }
                    next += 1;
                    recorded_gone += 1 + usize::from(pivot.r.is_some());
                }
                if !replaying || (last && front.len() > 0) {
                    // The search takes over, with every fully summed variable of the front.
                    replaying = false;
                    ready_search(waiting, recorded_step);
                    candidates.clear();
                    candidates
                        .extend((0..front.len()).filter(|&slot| front.is_summed(slot)).map(|slot| front.var[slot]));
                    for &v in candidates.iter() {
                        waiting.stale[v] = true;
                    }
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
    fn root(
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
            candidates.clear();
            candidates.extend(front.var.iter().copied());
            waiting.stale.resize(n, true);
            waiting.period.resize(n, 0);
            for &v in candidates.iter() {
                waiting.stale[v] = true;
                waiting.period[v] = 0;
            }
            self.eliminate_candidates(front, candidates, waiting, Step { index: 0, border: 0, last: true }, |_| 0)?;
            self.stats.delayed += candidates.len();
        }
        debug_assert_eq!(front.len(), 0, "the root eliminates every variable");
        Ok(())
    }

    /// Takes the recorded `pivot` if its variables are fully summed in the front and it passes
    /// its test again ([`Growth::replays`]).
    fn replay(&mut self, front: &mut Front, pivot: Scheduled, border: usize) -> bool {
        let sp = front.slot_of[pivot.p];
        let sr = pivot.r.map(|r| front.slot_of[r]);
        let fits = |slot: usize| slot != ABSENT && front.is_summed(slot);
        if !fits(sp) || !sr.is_none_or(fits) {
            return false;
        }
        match sr {
            None => front.load(&[sp]),
            Some(sr) => front.load(&[sp, sr]),
        }
        if !growth(front, sp, sr, border).is_some_and(|now| now.replays(pivot.growth, pivot.limits, border)) {
            return false;
        }
        match sr {
            None => self.pivot_one(front, sp),
            Some(sr) => self.pivot_two(front, sp, sr),
        }
        self.stats.replayed += 1;
        self.schedule.push(pivot);
        true
    }

    /// Eliminates fully summed variables while one passes the pivot tests.
    fn eliminate_candidates(
        &mut self,
        front: &mut Front,
        candidates: &mut Vec<usize>,
        waiting: &mut Waiting,
        Step { index: step, border, last }: Step,
        waited: impl Fn(usize) -> usize,
    ) -> Result<(), KktError> {
        // One pass over the candidates per step; at the last step, passes until all are gone (a
        // pivot changes the front, so a variable that waited may pass on the next pass).
        let gone = &mut waiting.gone;
        loop {
            let mut progress = false;
            gone.clear();
            gone.resize(candidates.len(), false);
            for c in 0..candidates.len() {
                let v = candidates[c];
                let period = waited(v);
                if gone[c] || !(last || waiting.stale[v] || waiting.period[v] != period) {
                    continue;
                }
                let limits = Thresholds::after_waiting(period);
                let start = self.index.len();
                let eliminated = match choose(front, front.slot_of[v], border, limits)? {
                    Choice::Delay => {
                        waiting.stale[v] = false;
                        waiting.period[v] = period;
                        continue;
                    }
                    Choice::One(slot) => {
                        let p = front.var[slot];
                        front.load(&[slot]);
                        let growth = growth(front, slot, None, border).unwrap_or(Growth::THRESHOLD);
                        self.pivot_one(front, slot);
                        self.schedule.push(Scheduled { step, p, r: None, limits, growth });
                        [Some(p), None]
                    }
                    Choice::Two(sp, sr) => {
                        let (p, r) = (front.var[sp], front.var[sr]);
                        front.load(&[sp, sr]);
                        let growth = growth(front, sp, Some(sr), border).unwrap_or(Growth::THRESHOLD);
                        self.pivot_two(front, sp, sr);
                        self.schedule.push(Scheduled { step, p, r: Some(r), limits, growth });
                        [Some(p), Some(r)]
                    }
                };
                for (flag, &u) in gone.iter_mut().zip(candidates.iter()) {
                    *flag |= eliminated.contains(&Some(u));
                }
                // The rows coupled to the pivot changed; so may the tests of the variables
                // coupled to those of them that are fully summed (their partners).
                let coupled = &self.index[start..];
                for (&u, &flag) in candidates.iter().zip(gone.iter()) {
                    if !flag && !waiting.stale[u] {
                        let slot_u = front.slot_of[u];
                        waiting.stale[u] = coupled.iter().any(|&w| {
                            w == u || (front.is_summed(front.slot_of[w]) && front.at(slot_u, front.slot_of[w]) != 0.0)
                        });
                    }
                }
                progress = true;
            }
            let mut keep = gone.iter().map(|g| !g);
            candidates.retain(|_| keep.next().unwrap_or(true));
            if !progress || !last {
                return Ok(());
            }
        }
    }

    fn pivot_one(&mut self, front: &mut Front, slot: usize) {
        let d = front.at(slot, slot);
        let p = front.var[slot];
        if d > 0.0 {
            self.inertia.positive += 1;
        } else {
            self.inertia.negative += 1;
        }
        let (start, first) = (self.index.len(), self.lower.len());
        let (index, lower) = (&mut self.index, &mut self.lower);
        index.reserve(front.len());
        lower.reserve(front.len());
        front.eliminate([slot], [[1.0 / d]], |v, [l]| {
            index.push(v);
            lower.push(l);
        });
        self.pivots.push(Pivot::One { p, inverse: 1.0 / d, start, end: self.index.len(), lower: first });
    }

    fn pivot_two(&mut self, front: &mut Front, sp: usize, sr: usize) {
        let (a, b, c) = (front.at(sp, sp), front.at(sr, sp), front.at(sr, sr));
        let det = a * c - b * b;
        if det < 0.0 {
            self.inertia.positive += 1;
            self.inertia.negative += 1;
        } else if a + c > 0.0 {
            self.inertia.positive += 2;
        } else {
            self.inertia.negative += 2;
        }
        let inverse = [[c / det, -b / det], [-b / det, a / det]];
        let (p, r) = (front.var[sp], front.var[sr]);
        let (start, first) = (self.index.len(), self.lower.len());
        let (index, lower) = (&mut self.index, &mut self.lower);
        index.reserve(front.len());
        lower.reserve(2 * front.len());
        front.eliminate([sp, sr], inverse, |v, [l1, l2]| {
            index.push(v);
            lower.push(l1);
            lower.push(l2);
        });
        self.stats.two_by_two += 1;
        self.pivots.push(Pivot::Two { p, r, inverse, start, end: self.index.len(), lower: first });
    }

    /// `y ← L⁻¹ y` for this stage's pivots.
    fn forward(&self, y: &mut [f64]) {
        for pivot in &self.pivots {
            match *pivot {
                Pivot::One { p, start, end, lower, .. } => {
                    let yp = y[p];
                    for (&i, &l) in self.index[start..end].iter().zip(&self.lower[lower..]) {
                        y[i] -= l * yp;
                    }
                }
                Pivot::Two { p, r, start, end, lower, .. } => {
                    let (yp, yr) = (y[p], y[r]);
                    for (e, &i) in self.index[start..end].iter().enumerate() {
                        let at = lower + 2 * e;
                        y[i] -= self.lower[at] * yp + self.lower[at + 1] * yr;
                    }
                }
            }
        }
    }

    /// `y ← D⁻¹ y` for this stage's pivots.
    fn diagonal(&self, y: &mut [f64]) {
        for pivot in &self.pivots {
            match *pivot {
                Pivot::One { p, inverse, .. } => y[p] *= inverse,
                Pivot::Two { p, r, inverse, .. } => {
                    let (yp, yr) = (y[p], y[r]);
                    y[p] = inverse[0][0] * yp + inverse[0][1] * yr;
                    y[r] = inverse[1][0] * yp + inverse[1][1] * yr;
                }
            }
        }
    }

    /// `y ← L⁻ᵀ y` for this stage's pivots.
    fn backward(&self, y: &mut [f64]) {
        for pivot in self.pivots.iter().rev() {
            match *pivot {
                Pivot::One { p, start, end, lower, .. } => {
                    let sum: f64 =
                        self.index[start..end].iter().zip(&self.lower[lower..]).map(|(&i, &l)| l * y[i]).sum();
                    y[p] -= sum;
                }
                Pivot::Two { p, r, start, end, lower, .. } => {
                    let (mut sp, mut sr) = (0.0, 0.0);
                    for (e, &i) in self.index[start..end].iter().enumerate() {
                        let at = lower + 2 * e;
                        sp += self.lower[at] * y[i];
                        sr += self.lower[at + 1] * y[i];
                    }
                    y[p] -= sp;
                    y[r] -= sr;
                }
            }
        }
    }
}

impl Factor {
    /// Drops the recorded pivot sequences, so that the next factorisation reusing this one
    /// searches for its pivots.
    pub fn forget_pivot_sequence(&mut self) {
        for stage in &mut self.stages {
            stage.schedule.clear();
        }
    }

    /// The inertia of the matrix.
    pub fn inertia(&self) -> Inertia {
        self.inertia
    }

    /// Front sizes, pivots and fill.
    pub fn stats(&self) -> FactorStats {
        self.stats
    }

    /// Overwrites `b` (original numbering) with `A⁻¹ b`; `work` is scratch of any length. The
    /// stages' pivots come in the order of the sweeps (the halves of a split before the root).
    pub fn solve_in_place(&self, b: &mut [f64], work: &mut Vec<f64>) {
        let n = self.order.len();
        work.clear();
        work.extend(self.order.iter().zip(&self.scale).map(|(&v, &s)| b[v] * s));
        let y = &mut work[..n];
        for stage in &self.stages {
            stage.forward(y);
        }
        for stage in &self.stages {
            stage.diagonal(y);
        }
        for stage in self.stages.iter().rev() {
            stage.backward(y);
        }
        for ((&v, &s), &yk) in self.order.iter().zip(&self.scale).zip(y.iter()) {
            b[v] = yk * s;
        }
    }
}
