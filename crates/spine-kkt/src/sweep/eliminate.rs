//! The elimination of a sweep: fully summed variables tested by the Bunch–Kaufman rule (with the
//! thresholds of [`super`]) and eliminated as 1×1 or 2×2 pivots.

use super::{Pivot, Scheduled, StageFactor, Step, Waiting};
use crate::front::Front;
use crate::pivot::{choose, growth, Choice, Growth, Thresholds};
use crate::KktError;

impl StageFactor {
    /// Eliminates fully summed variables while one passes the pivot tests.
    pub(super) fn eliminate_candidates(
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

    pub(super) fn pivot_one(&mut self, front: &mut Front, slot: usize) {
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

    pub(super) fn pivot_two(&mut self, front: &mut Front, sp: usize, sr: usize) {
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
}
