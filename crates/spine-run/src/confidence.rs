//! A census to a stated confidence: seeded starts of eq. (33) in batches of
//! [`CONFIDENCE_BATCH`] ([`Batches`]) until the Boender–Rinnooy Kan estimate gives P(a better
//! optimum unseen) ≤ P. One [`ConfidenceCensus`] settles the batches and applies the rule, on one
//! machine (`design::census_to`) and in [`crate::shard::merge`] for a census sharded batch by
//! batch on a cluster, so both give the same bytes.

use crate::error::RunError;
use spine_case::ValidDesign;
use spine_design::multistart::{ConfidenceRun, Settled};
use spine_design::{DesignResult, SolverRun};

/// Seeded starts per batch of a census to a stated confidence: the rule is checked after each
/// batch, so the census (and its bytes) does not depend on `--jobs`.
pub const CONFIDENCE_BATCH: usize = 100;

/// The batches of a census to a stated confidence: batch `b` (1-based) holds the seeded starts
/// `100(b − 1) + 1 ..= 100 b` (fewer in the last, at the cap), and batch 1 also the case's own
/// start 0.
#[derive(Clone, Copy, Debug)]
pub struct Batches {
    /// The cap on seeded starts (`multistart.starts`; 0: [`spine_case::MAX_STARTS`]), at most
    /// what the memory budget holds of this chain's runs.
    pub cap: usize,
}

impl Batches {
    pub fn new(valid: &ValidDesign) -> Self {
        let cap = match valid.multistart.starts {
            0 => spine_case::MAX_STARTS,
            n => n,
        };
        // The census keeps every run until it is settled: no more than the memory budget holds
        // (the census then ends at its cap, exit 3, with what it found).
        let fits = spine_stop::memory::budget() as f64 / spine_case::run_bytes(valid.problem.n_links());
        Self { cap: cap.min((fits as usize).saturating_sub(1).max(CONFIDENCE_BATCH)) }
    }

    /// How many batches the cap allows.
    pub fn count(&self) -> usize {
        self.cap.div_ceil(CONFIDENCE_BATCH)
    }

    /// The seeded starts of batch `b` (1-based), or `None` past the cap.
    pub fn seeded(&self, b: usize) -> Option<std::ops::RangeInclusive<usize>> {
        (1..=self.count()).contains(&b).then(|| (b - 1) * CONFIDENCE_BATCH + 1..=(b * CONFIDENCE_BATCH).min(self.cap))
    }

    /// Every start of batch `b`: its seeded starts, and start 0 in batch 1.
    pub fn starts(&self, b: usize) -> Vec<usize> {
        let own = (b == 1).then_some(0);
        own.into_iter().chain(self.seeded(b).into_iter().flatten()).collect()
    }
}

/// A census to a stated confidence as it grows: each batch's runs settled in start order, the
/// rule checked after each batch (one machine: `design::census_to`; a cluster: the merge of each
/// batch's shards, [`crate::shard::merge`]).
pub struct ConfidenceCensus<'a> {
    settled: Settled<'a>,
    target: f64,
    batches: Batches,
    done: usize,
    /// Seeded runs added so far.
    seeded: usize,
    reached: bool,
}

impl<'a> ConfidenceCensus<'a> {
    /// The census of the run from the case's own start (start 0).
    pub fn new(valid: &'a ValidDesign, target: f64, own: SolverRun) -> Result<Self, RunError> {
        let mut settled = Settled::new(&valid.problem, valid.solver());
        settled.add(own).map_err(RunError::Design)?;
        Ok(Self { settled, target, batches: Batches::new(valid), done: 0, seeded: 0, reached: false })
    }

    /// Batches added so far.
    pub fn batches(&self) -> usize {
        self.done
    }

    /// Adds the next batch's seeded runs in start order; whether the census is over (the
    /// estimate reached the target, or the cap).
    pub fn add_batch(&mut self, runs: Vec<SolverRun>) -> Result<bool, RunError> {
        for run in runs {
            self.settled.add(run).map_err(RunError::Design)?;
            self.seeded += 1;
        }
        self.done += 1;
        self.reached = self.settled.estimate().probability_better_unseen.is_some_and(|p| p <= self.target);
        Ok(self.reached || self.done >= self.batches.count())
    }

    /// The settled results in start order and how the census ran.
    pub fn finish(self) -> (Vec<DesignResult>, ConfidenceRun) {
        let run = ConfidenceRun {
            target: self.target,
            reached: self.reached,
            batches: self.done,
            batch: CONFIDENCE_BATCH,
            cap: self.batches.cap,
            seeded: self.seeded,
        };
        (self.settled.results(), run)
    }
}
