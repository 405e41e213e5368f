//! The numerical factorisation `P S A S Pᵀ = L D Lᵀ` (Pardiso's phase 22), and solves with it.
//!
//! `S` is a diagonal equilibration (a few passes of Ruiz's scaling, so that every row of `S A S`
//! has largest entry about 1), `P` the order of [`Analysis`]. Then the frontal sweep of each stage
//! ([`crate::sweep`]): one sweep; or, for a split order, the two halves at once (on two threads)
//! and the root front where they meet. `L` and `D` are the stages' pivots, in that order.
//!
//! No pivot is perturbed, so the inertia of `D` is the inertia of `A` (Sylvester's law). The
//! relaxed thresholds allow growth; the solver's iterative refinement and, where that stalls, one
//! GMRES correction ([`crate::SymmetricSolver::solve`]) repair the solution.

use crate::analysis::Analysis;
pub use crate::pivot::{BORDER_THRESHOLD, LAST_RESORT_THRESHOLD, PATIENCE, RELAXED_THRESHOLD, SINGULAR, THRESHOLD};
use crate::sweep::StageFactor;
pub use crate::sweep::{FactorStats, Inertia};
use crate::KktError;

/// Passes of Ruiz's equilibration from `S = I`.
const SCALING_PASSES: usize = 3;
/// From the scaling of the factorisation before (Ipopt's matrices change a little from one
/// factorisation to the next, so it is a close start), Ruiz's passes stop once a pass has changed
/// no scale factor by more than this factor (at most [`SCALING_PASSES`] passes). In eq. (33)'s
/// solves (N = 200, 1000) half the factorisations take one pass and a twentieth three, 1.6 on
/// average; a pass takes about 0.1 ms at N = 1000 (a fourteenth of a replayed factorisation).
const SCALING_SETTLED: f64 = 10.0;

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
    /// Factorises the matrix with these values (in the order of the analysed structure), on one
    /// thread.
    pub fn new(analysis: &Analysis, values: &[f64]) -> Result<Self, KktError> {
        Self::reusing(analysis, values, None, false)
    }

    /// [`Factor::new`], writing into the storage of an earlier factorisation (Ipopt factorises
    /// matrices of one structure hundreds of times; at N = 1000 `L` takes about 2 MB, and fresh
    /// pages cost a tenth of the factorisation).
    ///
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
                if two_threads {
                    // The first half goes to whichever thread takes it first: the helper, or this
                    // thread once the second half is done (a new thread can take a few tenths of
                    // a millisecond to start on a machine whose other core is idle).
                    let unclaimed = std::sync::Mutex::new(Some(&mut *first));
                    let claim = || unclaimed.lock().ok().and_then(|mut half| half.take());
                    let (one, two) = std::thread::scope(|scope| {
                        // Where no thread can be started, this thread takes both halves.
                        let helper =
                            std::thread::Builder::new().spawn_scoped(scope, || claim().map(|half| sweep(half, 0))).ok();
                        let two = sweep(second, 1);
                        let here = claim().map(|half| sweep(half, 0));
                        // A panic of the helper goes on in this thread.
                        let helped = helper
                            .and_then(|helper| helper.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
                        (here.or(helped), two)
                    });
                    one.unwrap_or_else(|| Err(KktError::Internal("the first half of the split was not swept".into())))?;
                    two?;
                } else {
                    sweep(first, 0)?;
                    sweep(second, 1)?;
                }
                let halves = [first.front(), second.front()];
                root.run(|f, recorded, work| f.root(analysis, halves, values, scale, recorded, work))
            }
            _ => Err(KktError::Internal(format!(
                "{} stages for an analysis of {}",
                self.stages.len(),
                analysis.stages.len()
            ))),
        }
    }

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
