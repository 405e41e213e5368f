//! Replaying a recorded sweep: the pivots of an earlier factorisation of a matrix of the same
//! structure taken again where they pass their test, and the search set up where one fails.

use super::{Scheduled, StageFactor, Waiting};
use crate::front::{Front, ABSENT};
use crate::pivot::growth;

/// The search takes over: every fully summed variable of the front is a candidate, to be tested
/// at its next chance.
pub(super) fn take_over(front: &Front, candidates: &mut Vec<usize>, stale: &mut [bool]) {
    candidates.clear();
    candidates.extend((0..front.len()).filter(|&slot| front.is_summed(slot)).map(|slot| front.var[slot]));
    for &v in candidates.iter() {
        stale[v] = true;
    }
}

impl StageFactor {
    /// Replays the recorded pivots of step `k` while they pass, counting them (`next`, and the
    /// variables they eliminated); `false` from the first that fails.
    pub(super) fn replay_step(
        &mut self,
        front: &mut Front,
        recorded: &[Scheduled],
        (next, gone): (&mut usize, &mut usize),
        k: usize,
        border: usize,
    ) -> bool {
        while let Some(&pivot) = recorded.get(*next).filter(|pivot| pivot.step == k) {
            if !self.replay(front, pivot, border) {
                return false;
            }
            *next += 1;
            *gone += 1 + usize::from(pivot.r.is_some());
        }
        true
    }

    /// Takes the recorded `pivot` if its variables are fully summed in the front and it passes
    /// its test again ([`Growth::replays`]).
    pub(super) fn replay(&mut self, front: &mut Front, pivot: Scheduled, border: usize) -> bool {
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
}

/// What only the search reads, set up when it first takes over: every waiting variable stale, no
/// waiting periods, and the step after which the recorded sweep had eliminated each variable
/// (`n`: never).
pub(super) fn prepare_search(n: usize, recorded: &[Scheduled], waiting: &mut Waiting, recorded_step: &mut Vec<usize>) {
    waiting.stale.fill(true);
    waiting.period.clear();
    waiting.period.resize(n, 0);
    recorded_step.clear();
    recorded_step.resize(if recorded.is_empty() { 0 } else { n }, n);
    for pivot in recorded {
        recorded_step[pivot.p] = pivot.step;
        if let Some(r) = pivot.r {
            recorded_step[r] = pivot.step;
        }
    }
}
