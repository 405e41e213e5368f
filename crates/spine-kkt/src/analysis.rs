//! The symbolic phase: the elimination order and, for each step of the frontal sweep, which
//! entries enter the front and which variables become fully summed (free to be pivots).

use crate::ordering::Ordering;
use crate::symmetric::Structure;

/// What the numerical factorisation needs to know about the structure, computed once per
/// structure (Pardiso's phase 11).
#[derive(Clone, Debug)]
pub struct Analysis {
    pub(crate) structure: Structure,
    pub(crate) ordering: Ordering,
    /// Entries entering at step `k` (when the `k`-th variable of the order joins the front):
    /// `(j, position of the value)` with `j ≤ k`, in the new numbering.
    pub(crate) enter_start: Vec<usize>,
    pub(crate) enter: Vec<(usize, usize)>,
    /// Variables (new numbering) whose last entry enters at step `k`: from then on their row of the
    /// front is complete and they may be eliminated.
    pub(crate) summed_start: Vec<usize>,
    pub(crate) summed: Vec<usize>,
    /// The widest front the order gives if no pivot is delayed.
    pub(crate) predicted_front: usize,
}

impl Analysis {
    /// Orders the structure's graph and lays out the sweep.
    pub fn new(structure: Structure) -> Self {
        let n = structure.order();
        let ordering = Ordering::new(&structure.adjacency());
        let mut count = vec![0usize; n + 1];
        let mut last: Vec<usize> = (0..n).collect();
        for (r, c, _) in structure.entries() {
            let (pr, pc) = (ordering.position[r], ordering.position[c]);
            count[pr.max(pc) + 1] += 1;
            last[pr] = last[pr].max(pc);
            last[pc] = last[pc].max(pr);
        }
        let enter_start = prefix_sums(&count);
        let mut next = enter_start.clone();
        let mut enter = vec![(0, 0); structure.stored()];
        for (r, c, e) in structure.entries() {
            let (pr, pc) = (ordering.position[r], ordering.position[c]);
            let k = pr.max(pc);
            enter[next[k]] = (pr.min(pc), e);
            next[k] += 1;
        }
        let mut by_last = vec![0usize; n + 1];
        for &l in &last {
            by_last[l + 1] += 1;
        }
        let summed_start = prefix_sums(&by_last);
        let mut next = summed_start.clone();
        let mut summed = vec![0; n];
        for (v, &l) in last.iter().enumerate() {
            summed[next[l]] = v;
            next[l] += 1;
        }
        // Front width without delays: variables that have entered and are not yet fully summed,
        // plus those that become summed at this step.
        let mut width = 0usize;
        let mut predicted_front = 0;
        for k in 0..n {
            width += 1;
            predicted_front = predicted_front.max(width);
            width -= summed_start[k + 1] - summed_start[k];
        }
        Self { structure, ordering, enter_start, enter, summed_start, summed, predicted_front }
    }

    /// The variables (new numbering) that become fully summed at step `k`.
    pub(crate) fn summed_at(&self, k: usize) -> &[usize] {
        &self.summed[self.summed_start[k]..self.summed_start[k + 1]]
    }

    /// The order `n` of the matrix.
    pub fn order(&self) -> usize {
        self.structure.order()
    }

    /// The structure analysed.
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The widest front of the sweep when no pivot is delayed.
    pub fn predicted_front(&self) -> usize {
        self.predicted_front
    }

    /// How many dense rows the order put first.
    pub fn dense_rows(&self) -> usize {
        self.ordering.dense
    }
}

fn prefix_sums(count: &[usize]) -> Vec<usize> {
    let mut sums = count.to_vec();
    for i in 1..sums.len() {
        sums[i] += sums[i - 1];
    }
    sums
}
