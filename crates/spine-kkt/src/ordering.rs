//! The elimination order of the frontal factorisation: the few dense rows first (they stay in the
//! front from start to end), then the rest by reverse Cuthill–McKee, which finds the band of a
//! chain-like graph so that the front stays as narrow as the band.

use std::collections::VecDeque;

/// A row is dense when its degree exceeds this many times the median degree (and [`DENSE_MIN`]).
/// The KKT matrix of eq. (33) has a handful of such rows (the slider multipliers and constraints,
/// the end-displacement row), each touching every link; the rest have a few neighbours.
pub const DENSE_FACTOR: usize = 4;
/// Rows with at most this many neighbours are never treated as dense.
pub const DENSE_MIN: usize = 16;

/// Orders of at least this many variables have their leaves postponed (`postpone_leaves`).
/// Measured on eq. (33)'s scaled family: per Ipopt iteration 16 % cheaper at N = 100 (order 1003)
/// and 12 % at N = 200, one factorisation 31 % cheaper at N = 1000. Below it the waits cost
/// little, and the order stays plain reverse Cuthill–McKee: eq. (33) is multimodal, Ipopt's path
/// depends on rounding, and with postponed leaves fig. 6's single start (N = 10) ends on another
/// local optimum, 7 % higher; so the paper cases keep the order they were checked with.
pub const POSTPONE_LEAVES_FROM: usize = 1000;

/// An elimination order: `order[k]` is the original index of the `k`-th variable eliminated (at
/// the latest), `position` its inverse.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ordering {
    pub order: Vec<usize>,
    pub position: Vec<usize>,
    /// How many dense rows lead the order.
    pub dense: usize,
    /// In a split order ([`Ordering::split`]), where the second half starts.
    pub split: Option<usize>,
}

impl Ordering {
    /// Dense rows first (in their original order), then reverse Cuthill–McKee on the graph of the
    /// rest, one connected component after another, with the leaves postponed from
    /// [`POSTPONE_LEAVES_FROM`] variables on.
    pub fn new(adjacent: &[Vec<usize>]) -> Self {
        Self::build(adjacent, false)
    }

    /// [`Ordering::new`] cut in two halves for two sweeps from the two ends of the chain toward
    /// its middle: the dense rows, then the first half of the reverse Cuthill–McKee order, then the
    /// second half reversed (so that it, too, starts at an end of the band), each with its leaves
    /// postponed; `split` is where the second half starts.
    pub fn split(adjacent: &[Vec<usize>]) -> Self {
        Self::build(adjacent, true)
    }

    fn build(adjacent: &[Vec<usize>], split: bool) -> Self {
        let n = adjacent.len();
        let mut degrees: Vec<usize> = adjacent.iter().map(Vec::len).collect();
        degrees.sort_unstable();
        let median = degrees.get(n / 2).copied().unwrap_or(0);
        let threshold = DENSE_MIN.max(DENSE_FACTOR * median);
        let is_dense: Vec<bool> = adjacent.iter().map(|a| a.len() > threshold).collect();
        let mut order: Vec<usize> = (0..n).filter(|&v| is_dense[v]).collect();
        let dense = order.len();
        // The graph without the dense rows; degrees count only the remaining neighbours.
        let sparse: Vec<Vec<usize>> = adjacent
            .iter()
            .enumerate()
            .map(|(v, a)| if is_dense[v] { Vec::new() } else { a.iter().copied().filter(|&u| !is_dense[u]).collect() })
            .collect();
        let mut placed = is_dense.clone();
        // Each variable's breadth-first level in its component's Cuthill–McKee order.
        let mut level = vec![0; n];
        let mut rest = Vec::with_capacity(n - dense);
        for seed in 0..n {
            if placed[seed] {
                continue;
            }
            let start = peripheral_node(&sparse, seed);
            cuthill_mckee(&sparse, start, &mut placed, &mut rest, &mut level);
        }
        rest.reverse();
        let mut halves = None;
        if split && rest.len() >= 2 {
            // The second half runs from its end of the band to the cut level by level, each level
            // in the order the first half (and one sweep) has its levels.
            let second = rest.split_off(rest.len() / 2);
            let mut levels: Vec<&[usize]> = second.chunk_by(|&a, &b| level[a] == level[b]).collect();
            levels.reverse();
            let second = levels.concat();
            order.extend(postpone_leaves(&sparse, rest));
            halves = Some(order.len());
            order.extend(postpone_leaves(&sparse, second));
        } else if n >= POSTPONE_LEAVES_FROM {
            order.extend(postpone_leaves(&sparse, rest));
        } else {
            order.extend(rest);
        }
        let mut position = vec![0; n];
        for (k, &v) in order.iter().enumerate() {
            position[v] = k;
        }
        Self { order, position, dense, split: halves }
    }
}

/// Moves every leaf of the sparse graph (a variable with one neighbour, such as an inequality's
/// slack, coupled only to its constraint row) to just after the last of its neighbour's other
/// neighbours. The neighbour then becomes fully summed at the step the leaf enters, so the two can
/// be a pivot at once; in the reverse Cuthill–McKee order the leaf (whose largest entry is in that
/// row when its own diagonal is small) would wait for the row: 13 steps per slack in a KKT matrix
/// of eq. (33) at N = 1000, two thirds of all waits. `order` may be part of the graph (one half
/// of a split order): a leaf whose row is outside it stays where it is, and only the row's
/// neighbours inside it count.
fn postpone_leaves(sparse: &[Vec<usize>], order: Vec<usize>) -> Vec<usize> {
    let n = sparse.len();
    let mut position = vec![usize::MAX; n];
    for (k, &v) in order.iter().enumerate() {
        position[v] = k;
    }
    let inside = |v: usize| position[v] != usize::MAX;
    let is_leaf = |v: usize| sparse[v].len() == 1 && sparse[sparse[v][0]].len() > 1 && inside(sparse[v][0]);
    // `after[v]`: the leaves placed right after `v`.
    let mut after: Vec<Vec<usize>> = vec![Vec::new(); n];
    for &leaf in &order {
        if is_leaf(leaf) {
            let parent = sparse[leaf][0];
            let last = sparse[parent]
                .iter()
                .copied()
                .filter(|&u| !is_leaf(u) && inside(u))
                .chain(std::iter::once(parent))
                .max_by_key(|&u| position[u])
                .unwrap_or(parent);
            after[last].push(leaf);
        }
    }
    let mut out = Vec::with_capacity(order.len());
    for &v in &order {
        if !is_leaf(v) {
            out.push(v);
            out.extend_from_slice(&after[v]);
        }
    }
    out
}

/// Breadth-first levels from `root`: (the nodes of the last level, the number of levels).
fn last_level(adjacent: &[Vec<usize>], root: usize) -> (Vec<usize>, usize) {
    let mut depth = vec![usize::MAX; adjacent.len()];
    depth[root] = 0;
    let mut queue = VecDeque::from([root]);
    let mut deepest = 0;
    let mut visited = Vec::new();
    while let Some(v) = queue.pop_front() {
        visited.push(v);
        deepest = deepest.max(depth[v]);
        for &u in &adjacent[v] {
            if depth[u] == usize::MAX {
                depth[u] = depth[v] + 1;
                queue.push_back(u);
            }
        }
    }
    (visited.into_iter().filter(|&v| depth[v] == deepest).collect(), deepest)
}

/// A pseudo-peripheral node of `seed`'s component (George and Liu): repeatedly jump to a node of
/// least degree in the last breadth-first level while the number of levels grows.
fn peripheral_node(adjacent: &[Vec<usize>], seed: usize) -> usize {
    let mut root = seed;
    let (mut level, mut eccentricity) = last_level(adjacent, root);
    loop {
        let Some(&candidate) = level.iter().min_by_key(|&&v| (adjacent[v].len(), v)) else {
            return root;
        };
        let (next_level, next_eccentricity) = last_level(adjacent, candidate);
        if next_eccentricity <= eccentricity {
            return root;
        }
        root = candidate;
        level = next_level;
        eccentricity = next_eccentricity;
    }
}

/// Cuthill–McKee from `start`: breadth first, neighbours by increasing degree.
fn cuthill_mckee(
    adjacent: &[Vec<usize>],
    start: usize,
    placed: &mut [bool],
    order: &mut Vec<usize>,
    level: &mut [usize],
) {
    placed[start] = true;
    level[start] = 0;
    let mut head = order.len();
    order.push(start);
    let mut next = Vec::new();
    while head < order.len() {
        let v = order[head];
        head += 1;
        next.clear();
        next.extend(adjacent[v].iter().copied().filter(|&u| !placed[u]));
        next.sort_unstable_by_key(|&u| (adjacent[u].len(), u));
        for &u in &next {
            placed[u] = true;
            level[u] = level[v] + 1;
            order.push(u);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The adjacency lists of a graph of `n` nodes with these edges.
    fn graph(n: usize, edges: impl IntoIterator<Item = (usize, usize)>) -> Vec<Vec<usize>> {
        let mut adjacent = vec![Vec::new(); n];
        for (a, b) in edges {
            adjacent[a].push(b);
            adjacent[b].push(a);
        }
        adjacent
    }

    /// Whether `order` holds each of `0..n` once.
    fn is_permutation(order: &[usize]) -> bool {
        let mut sorted = order.to_vec();
        sorted.sort_unstable();
        sorted.iter().copied().eq(0..order.len())
    }

    /// A path 0–1–…–9 given in a scrambled numbering, with one node joined to all others.
    #[test]
    fn finds_the_band_of_a_scrambled_path_and_puts_the_dense_node_first() {
        let n = 40;
        let label = |i: usize| (i * 17) % (n - 1); // a permutation of 0..n-1
        let hub = n - 1;
        let path = (0..n - 2).map(|i| (label(i), label(i + 1)));
        let adjacent = graph(n, path.chain((0..hub).map(|v| (v, hub))));
        let ordering = Ordering::new(&adjacent);
        assert_eq!(ordering.dense, 1);
        assert_eq!(ordering.order[0], hub);
        for i in 0..n - 2 {
            let (a, b) = (ordering.position[label(i)], ordering.position[label(i + 1)]);
            assert_eq!(a.abs_diff(b), 1, "path neighbours {i}, {} are not adjacent in the order", i + 1);
        }
    }

    /// A split order of a path with a hub: the hub first, then the first half of the path from one
    /// end to the middle, then the second half from the other end to the middle; each half keeps
    /// path neighbours next to each other, and the last variables of the two halves are the two
    /// sides of the cut.
    #[test]
    fn a_split_order_sweeps_each_half_of_a_path_from_its_end_to_the_middle() {
        let n = 5001;
        let hub = n - 1;
        let adjacent = graph(n, (0..n - 2).map(|i| (i, i + 1)).chain((0..hub).map(|v| (v, hub))));
        let ordering = Ordering::split(&adjacent);
        assert_eq!((ordering.dense, ordering.order[0]), (1, hub));
        let split = ordering.split.expect("a split order");
        assert_eq!(split, 1 + (n - 1) / 2);
        // Each half starts at an end of the path (an end is a leaf, postponed past its neighbour's
        // other neighbour), then follows the path.
        let starts = [&ordering.order[1..4], &ordering.order[split..split + 3]];
        let at_end = |end: usize| starts.iter().position(|start| start.contains(&end));
        assert!(at_end(0).is_some() && at_end(n - 2).is_some() && at_end(0) != at_end(n - 2), "{starts:?}");
        for half in [4..split, split + 3..n] {
            for pair in ordering.order[half].windows(2) {
                assert_eq!(pair[0].abs_diff(pair[1]), 1, "{pair:?} are not path neighbours");
            }
        }
        assert_eq!(ordering.order[split - 1].abs_diff(ordering.order[n - 1]), 1, "the halves meet at the cut");
        assert!(is_permutation(&ordering.order), "a permutation");
        assert_eq!(Ordering::new(&adjacent).split, None);
    }

    /// The second half of a split ladder (two rails joined by rungs) runs toward the cut one
    /// breadth-first level after another, and keeps each level in the order the unsplit order has
    /// it (a plain reversal would reverse it too, and with it which of two coupled variables
    /// becomes a pivot first).
    #[test]
    fn the_second_half_of_a_split_order_keeps_each_level_in_the_unsplit_order() {
        let rungs = 1500;
        let n = 2 * rungs;
        let rails = (0..2 * rungs - 2).map(|v| (v, v + 2));
        let adjacent = graph(n, (0..rungs).map(|i| (2 * i, 2 * i + 1)).chain(rails));
        let (split, unsplit) = (Ordering::split(&adjacent), Ordering::new(&adjacent));
        let cut = split.split.expect("a split order");
        // Levels from where the unsplit Cuthill–McKee order starts (the reverse order's end).
        let (mut level, mut placed, mut order) = (vec![0; n], vec![false; n], Vec::new());
        cuthill_mckee(&adjacent, unsplit.order[n - 1], &mut placed, &mut order, &mut level);
        let second = &unsplit.order[cut..];
        let mut same_level = 0;
        for pair in second.windows(2) {
            if level[pair[0]] == level[pair[1]] {
                assert!(split.position[pair[0]] < split.position[pair[1]], "{pair:?} swapped");
                same_level += 1;
            }
        }
        assert!(same_level >= rungs / 2 - 2, "{same_level} pairs in one level");
        // Level by level toward the cut: the levels of the split's second half never decrease.
        let levels: Vec<usize> = split.order[cut..].iter().map(|&v| level[v]).collect();
        assert!(levels.windows(2).all(|w| w[0] <= w[1]), "the second half does not run toward the cut");
    }

    /// A path of rows, each with a leaf (a slack) hanging on it: from [`POSTPONE_LEAVES_FROM`]
    /// variables on, every leaf comes after its row and all the row's other neighbours, so row and
    /// leaf are fully summed at the same step; below it, the plain order.
    #[test]
    fn leaves_follow_the_last_neighbour_of_their_row_in_large_orders() {
        for rows in [300, 600] {
            let n = 2 * rows;
            let adjacent = graph(n, (0..rows - 1).map(|i| (i, i + 1)).chain((0..rows).map(|i| (i, rows + i))));
            let ordering = Ordering::new(&adjacent);
            let p = &ordering.position;
            let leaves_last = (0..rows).all(|i| {
                let leaf = rows + i;
                adjacent[i].iter().filter(|&&u| u != leaf).chain([&i]).all(|&u| p[u] < p[leaf])
            });
            assert_eq!(leaves_last, n >= POSTPONE_LEAVES_FROM, "{n} variables");
            assert!(is_permutation(&ordering.order), "a permutation");
        }
    }
}
