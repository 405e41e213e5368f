//! The symbolic phase: the elimination order and, for each step of the frontal sweep, which
//! entries enter the front and which variables become fully summed (free to be pivots).
//!
//! A large chain is cut in two halves ([`SPLIT_FROM`]): each half is swept from its end of the
//! chain toward the middle (the two sweeps are independent, and run at once on two threads), and
//! what is left of their fronts (the dense rows, the variables coupled across the cut, and any
//! pivot they delayed) is summed into a root front that is eliminated last.

use crate::ordering::Ordering;
use crate::symmetric::Structure;

/// Orders of at least this many variables are split in two halves (N ≥ 600 links in eq. (33),
/// whose KKT matrix has order 10 N + 3). Measured in a refined N = 1000 solve, factorisations and
/// solves together: at the 400-link level (order 4003) the split saved in the factorisations what
/// it lost in the solves (73 ms against 74), at the 800- and 1000-link levels 8 % (the solves
/// lose because the split's `L` is larger and half of it was written by the other core). The
/// paper's cases (N ≤ 50) are never split.
pub const SPLIT_FROM: usize = 6000;
/// A split whose root front would hold more variables than this (the dense rows and those coupled
/// across the cut; the root costs the cube of its width) is not taken.
pub const ROOT_LIMIT: usize = 64;

/// One frontal sweep: the variables it brings in, in order, and what enters and becomes fully
/// summed at each of its steps.
#[derive(Clone, Debug)]
pub(crate) struct Stage {
    /// The variables (new numbering) in the order they enter the front: step `t` brings in
    /// `vars[t]`.
    pub(crate) vars: Vec<usize>,
    /// Entries entering at step `t`: `(j, position of the value)` with `j` already in the front
    /// (new numbering).
    pub(crate) enter_start: Vec<usize>,
    pub(crate) enter: Vec<(usize, usize)>,
    /// Variables (new numbering) whose last entry of the stage enters at step `t`: from then on
    /// their row of the front is complete and they may be eliminated.
    pub(crate) summed_start: Vec<usize>,
    pub(crate) summed: Vec<usize>,
    /// Whether the stage ends the factorisation: its last step eliminates every variable left.
    /// A half of a split leaves what it cannot eliminate to the root.
    pub(crate) ends: bool,
}

impl Stage {
    /// The variables (new numbering) that become fully summed at step `t`.
    pub(crate) fn summed_at(&self, t: usize) -> &[usize] {
        &self.summed[self.summed_start[t]..self.summed_start[t + 1]]
    }

    /// The entries entering at step `t`.
    pub(crate) fn entering(&self, t: usize) -> &[(usize, usize)] {
        &self.enter[self.enter_start[t]..self.enter_start[t + 1]]
    }

    /// The number of steps.
    pub(crate) fn len(&self) -> usize {
        self.vars.len()
    }
}

/// What the numerical factorisation needs to know about the structure, computed once per
/// structure (Pardiso's phase 11).
#[derive(Clone, Debug)]
pub struct Analysis {
    pub(crate) structure: Structure,
    pub(crate) ordering: Ordering,
    /// One sweep, or the two halves of a split.
    pub(crate) stages: Vec<Stage>,
    /// After a split, the entries that couple the two halves, entered into the root front:
    /// `(i, j, position of the value)` in the new numbering.
    pub(crate) crossing: Vec<(usize, usize, usize)>,
    /// The widest front the order gives if no pivot is delayed.
    pub(crate) predicted_front: usize,
}

impl Analysis {
    /// Orders the structure's graph and lays out the sweep(s): split in two halves and a root
    /// when `split` allows it, the order has at least [`SPLIT_FROM`] variables and the root would
    /// hold at most [`ROOT_LIMIT`].
    pub fn new(structure: Structure, split: bool) -> Self {
        let adjacent = structure.adjacency();
        let split = (split && structure.order() >= SPLIT_FROM)
            .then(|| Ordering::split(&adjacent))
            .filter(|ordering| root_width(ordering, &adjacent) <= ROOT_LIMIT);
        let ordering = split.unwrap_or_else(|| Ordering::new(&adjacent));
        let (stages, crossing) = lay_out(&structure, &ordering);
        let predicted_front = stages.iter().map(Stage::predicted_front).max().unwrap_or(0);
        Self { structure, ordering, stages, crossing, predicted_front }
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

    /// Whether the sweep is split in two halves and a root.
    pub fn is_split(&self) -> bool {
        self.stages.len() == 2
    }
}

impl Stage {
    /// Front width without delays: variables that have entered and are not yet fully summed, plus
    /// those that become summed at this step.
    fn predicted_front(&self) -> usize {
        let (mut width, mut widest) = (0usize, 0usize);
        for t in 0..self.len() {
            width += 1;
            widest = widest.max(width);
            width -= self.summed_at(t).len();
        }
        widest
    }
}

/// The root front's width without delays in a split order: the dense rows and every variable
/// with a neighbour in the other half.
fn root_width(ordering: &Ordering, adjacent: &[Vec<usize>]) -> usize {
    let (Some(split), dense) = (ordering.split, ordering.dense) else { return 0 };
    let half = |v: usize| ordering.position[v] >= split;
    let crossing = (0..adjacent.len())
        .filter(|&v| {
            ordering.position[v] >= dense
                && adjacent[v].iter().any(|&u| ordering.position[u] >= dense && half(u) != half(v))
        })
        .count();
    dense + crossing
}

/// The stages of the order and, when it is split, the entries coupling its halves.
///
/// Without a split one stage brings in every variable in the order's numbering; an entry enters
/// when the later of its two variables does, and a variable is fully summed once its last entry
/// has entered. With a split at `h` (dense rows `0..d`), the first half brings in `0..h`, the
/// second the dense rows and then `h..n`; an entry belongs to the half that holds both its
/// variables (an entry of two dense rows to the first), and an entry between `d..h` and `h..n`
/// to the root. A variable is fully summed in its half only if all its entries are there; the
/// dense rows, which both halves update, only in the root.
fn lay_out(structure: &Structure, ordering: &Ordering) -> (Vec<Stage>, Vec<(usize, usize, usize)>) {
    let n = structure.order();
    let dense = ordering.dense;
    let vars: Vec<Vec<usize>> = match ordering.split {
        None => vec![(0..n).collect()],
        Some(h) => vec![(0..h).collect(), (0..dense).chain(h..n).collect()],
    };
    // The stage of an entry between `lo ≤ hi` (new numbering), `None` for the root.
    let stage_of = |lo: usize, hi: usize| match ordering.split {
        None => Some(0),
        Some(h) if hi < h => Some(0),
        Some(h) if lo < dense || lo >= h => Some(1),
        Some(_) => None,
    };
    let mut step = vec![vec![usize::MAX; n]; vars.len()];
    for (s, list) in vars.iter().enumerate() {
        for (t, &v) in list.iter().enumerate() {
            step[s][v] = t;
        }
    }
    // Per stage, the last step at which each variable's entries enter; whether a variable has
    // entries outside the stage.
    let mut last: Vec<Vec<usize>> = step.clone();
    let mut elsewhere = vec![0usize; n];
    let mut crossing = Vec::new();
    for (r, c, e) in structure.entries() {
        let (pr, pc) = (ordering.position[r], ordering.position[c]);
        let (lo, hi) = (pr.min(pc), pr.max(pc));
        match stage_of(lo, hi) {
            Some(s) => {
                let t = step[s][hi];
                last[s][lo] = last[s][lo].max(t);
                last[s][hi] = last[s][hi].max(t);
                elsewhere[lo] |= 1 << (s + 1);
                elsewhere[hi] |= 1 << (s + 1);
            }
            None => {
                crossing.push((pr, pc, e));
                elsewhere[lo] |= 1;
                elsewhere[hi] |= 1;
            }
        }
    }
    let split = ordering.split.is_some();
    let stages = vars
        .iter()
        .enumerate()
        .map(|(s, list)| {
            // An entry enters with the later of its two variables.
            let entries = || {
                structure.entries().filter_map(|(r, c, e)| {
                    let (pr, pc) = (ordering.position[r], ordering.position[c]);
                    let (lo, hi) = (pr.min(pc), pr.max(pc));
                    (stage_of(lo, hi) == Some(s)).then(|| (step[s][hi], (lo, e)))
                })
            };
            let (enter_start, enter) = group_by_step(list.len(), entries);
            // Fully summed in this stage: every entry here (and, after a split, not a dense row).
            let summable = |v: usize| !split || (v >= dense && elsewhere[v] & !(1 << (s + 1)) == 0);
            let finished = || list.iter().filter(|&&v| summable(v)).map(|&v| (last[s][v], v));
            let (summed_start, summed) = group_by_step(list.len(), finished);
            Stage { vars: list.clone(), enter_start, enter, summed_start, summed, ends: !split }
        })
        .collect();
    (stages, crossing)
}

/// The `(step, item)` pairs that `items` gives (twice) grouped by step `0..steps` (a stable
/// counting sort): where each step's group starts, and the items, step after step, each step's in
/// the order given.
fn group_by_step<T: Copy + Default, I: Iterator<Item = (usize, T)>>(
    steps: usize,
    items: impl Fn() -> I,
) -> (Vec<usize>, Vec<T>) {
    let mut start = vec![0usize; steps + 1];
    for (t, _) in items() {
        start[t + 1] += 1;
    }
    for t in 0..steps {
        start[t + 1] += start[t];
    }
    let mut next = start.clone();
    let mut grouped = vec![T::default(); start[steps]];
    for (t, item) in items() {
        grouped[next[t]] = item;
        next[t] += 1;
    }
    (start, grouped)
}
