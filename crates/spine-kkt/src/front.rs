//! The front of the sweep: a small dense symmetric matrix over the variables that have entered and
//! are not yet eliminated, stored by its lower triangle (slot `i` keeps `a_ij` for `j ≤ i`) with a
//! row stride that grows on demand. The Schur updates, which are most of the work, touch one
//! triangle only.

/// Marks a variable that is not in the front.
pub(crate) const ABSENT: usize = usize::MAX;

/// What [`Front::scan`] finds in one column.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColumnScan {
    /// The largest off-diagonal magnitude outside the dense rows, and its first row.
    pub largest: f64,
    pub row: Option<usize>,
    /// The largest magnitude among the fully summed rows outside the dense rows, and its last row.
    pub summed_largest: f64,
    pub summed_row: Option<usize>,
    /// The largest magnitude in the dense rows.
    pub border: f64,
}

#[derive(Clone, Debug)]
pub(crate) struct Front {
    stride: usize,
    /// Row-major `stride × stride`; only the lower triangle of the leading `len × len` block is in
    /// use.
    a: Vec<f64>,
    /// The variable (new numbering) of each slot.
    pub var: Vec<usize>,
    /// The slot of each variable, or [`ABSENT`].
    pub slot_of: Vec<usize>,
    /// Whether the variable of each slot is fully summed.
    summed: Vec<bool>,
    /// The pivot rows during an elimination (kept to avoid an allocation per pivot).
    scratch: Vec<f64>,
    /// The slots whose columns `scratch` holds.
    loaded: Vec<usize>,
    /// Whether no dense row (variables numbered below the `border` of the tests, which enter
    /// first) has left the front: then they hold the first slots.
    dense_first: bool,
    /// The number of dense rows.
    dense: usize,
}

impl Front {
    /// A front for a sweep of order `n` whose first `dense` variables are the dense rows.
    pub fn new(n: usize, capacity: usize, dense: usize) -> Self {
        let stride = capacity.max(4);
        Self {
            stride,
            a: vec![0.0; stride * stride],
            var: Vec::with_capacity(stride),
            summed: Vec::with_capacity(stride),
            slot_of: vec![ABSENT; n],
            scratch: Vec::new(),
            loaded: Vec::new(),
            dense_first: true,
            dense,
        }
    }

    /// Empties the front for a sweep of order `n` whose first `dense` variables are the dense
    /// rows.
    pub fn clear(&mut self, n: usize, dense: usize) {
        self.dense_first = true;
        self.dense = dense;
        // `slot_of` is `ABSENT` except for the variables in the front (after a complete sweep:
        // none).
        for &v in &self.var {
            self.slot_of[v] = ABSENT;
        }
        self.var.clear();
        self.summed.clear();
        self.slot_of.resize(n, ABSENT);
    }

    pub fn len(&self) -> usize {
        self.var.len()
    }

    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        self.a[i * self.stride + j]
    }

    /// Column `c` of the front, `len` entries, in its two stored pieces: row `c` of the triangle up
    /// to the diagonal, then column `c` below it.
    fn column_parts(&self, c: usize) -> (&[f64], impl Iterator<Item = f64> + '_) {
        let s = self.stride;
        (&self.a[c * s..c * s + c + 1], (c + 1..self.len()).map(move |i| self.a[i * s + c]))
    }

    /// Adds variable `v` with an empty row and column; returns its slot.
    pub fn push(&mut self, v: usize) -> usize {
        let slot = self.len();
        if slot == self.stride {
            self.grow();
        }
        let s = self.stride;
        self.a[slot * s..slot * s + slot + 1].fill(0.0);
        self.var.push(v);
        self.summed.push(false);
        self.slot_of[v] = slot;
        slot
    }

    fn grow(&mut self) {
        let old = self.stride;
        let stride = 2 * old;
        let mut a = vec![0.0; stride * stride];
        for i in 0..self.len() {
            a[i * stride..i * stride + old].copy_from_slice(&self.a[i * old..(i + 1) * old]);
        }
        self.a = a;
        self.stride = stride;
    }

    /// Adds `value` at `(i, j)` and `(j, i)` (once on the diagonal).
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        self.a[i * self.stride + j] += value;
    }

    /// Sums `other` into this front (an extend-add): its variables that are not here yet join,
    /// its entries are added, and a variable fully summed in either is fully summed here.
    pub fn absorb(&mut self, other: &Front) {
        let mut slots = Vec::with_capacity(other.len());
        for (i, &v) in other.var.iter().enumerate() {
            let slot = if self.slot_of[v] == ABSENT { self.push(v) } else { self.slot_of[v] };
            self.summed[slot] |= other.summed[i];
            slots.push(slot);
        }
        for (i, &slot_i) in slots.iter().enumerate() {
            for (j, &slot_j) in slots[..=i].iter().enumerate() {
                self.add(slot_i, slot_j, other.a[i * other.stride + j]);
            }
        }
    }

    /// Adds `value` at `(last, j)` and `(j, last)` (once on the diagonal), `last` the newest slot.
    #[inline]
    pub fn add_to_last(&mut self, j: usize, value: f64) {
        let last = self.len() - 1;
        self.a[last * self.stride + j] += value;
    }

    /// One pass over column `c` for the pivot tests:
    /// the largest `|a_ic|` over rows `i ≠ c` whose variable is not below `border` (the dense
    /// rows, numbered first) and its first row; the last row of largest `|a_ic|` among those whose
    /// variable is fully summed; and the largest entry in the dense rows. Rows in `skip` are left
    /// out.
    pub fn scan(&self, c: usize, skip: usize, border: usize) -> ColumnScan {
        let mut scan = ColumnScan { largest: 0.0, row: None, summed_largest: 0.0, summed_row: None, border: 0.0 };
        let mut visit = |i: usize, x: f64| {
            let v = x.abs();
            if self.var[i] < border {
                scan.border = scan.border.max(v);
            } else if i != c && i != skip {
                if v > scan.largest {
                    scan.largest = v;
                    scan.row = Some(i);
                }
                if self.summed[i] && (scan.summed_row.is_none() || v >= scan.summed_largest) {
                    scan.summed_largest = v;
                    scan.summed_row = Some(i);
                }
            }
        };
        // The column's two parts as two plain loops (row `c` up to the diagonal, then down the
        // rows below it): a chained iterator cost a branch per entry.
        let (upper, below) = self.column_parts(c);
        for (i, &x) in upper.iter().enumerate() {
            visit(i, x);
        }
        for (i, x) in (c + 1..).zip(below) {
            visit(i, x);
        }
        scan
    }

    /// Marks the variable in `slot` fully summed.
    pub fn mark_summed(&mut self, slot: usize) {
        self.summed[slot] = true;
    }

    /// Whether the variable in `slot` is fully summed.
    pub fn is_summed(&self, slot: usize) -> bool {
        self.summed[slot]
    }

    /// Copies the columns of the pivot slots into the pivot rows that [`Front::loaded`] reads and
    /// [`Front::eliminate`] uses.
    pub fn load(&mut self, pivots: &[usize]) {
        let mut scratch = std::mem::take(&mut self.scratch);
        scratch.clear();
        self.loaded.clear();
        for &c in pivots {
            let (upper, below) = self.column_parts(c);
            scratch.extend_from_slice(upper);
            scratch.extend(below);
            self.loaded.push(c);
        }
        self.scratch = scratch;
    }

    /// The `k`-th column loaded by [`Front::load`], `len` entries.
    pub fn loaded(&self, k: usize) -> &[f64] {
        let len = self.len();
        &self.scratch[k * len..(k + 1) * len]
    }

    /// The largest `|a_ic|` of a loaded column `c` over the rows `i ∉ {c, skip}` whose variable is
    /// not below `border`, and the largest over the rows whose variable is (the dense rows).
    pub fn loaded_maxima(&self, k: usize, skip: usize, border: usize) -> (f64, f64) {
        let c = self.loaded[k];
        let column = self.loaded(k);
        let largest_of = |values: &[f64]| values.iter().fold(0.0f64, |m, x| if x.abs() > m { x.abs() } else { m });
        if !self.dense_first {
            let (mut largest, mut dense) = (0.0f64, 0.0f64);
            for (i, (&x, &var)) in column.iter().zip(&self.var).enumerate() {
                let v = x.abs();
                if var < border {
                    dense = dense.max(v);
                } else if i != c && i != skip {
                    largest = largest.max(v);
                }
            }
            return (largest, dense);
        }
        // The dense rows enter first and hold the first slots: runs of the column, no test per
        // entry. The values are finite, so a plain comparison is `f64::max`, and cheaper.
        debug_assert!(border == 0 || border == self.dense, "the border is the dense rows or none");
        let dense_slots = border.min(column.len());
        let dense = largest_of(&column[..dense_slots]);
        let (c, skip) = (c.min(skip), c.max(skip));
        let sparse = &column[dense_slots..];
        let mut largest = 0.0f64;
        // The rows outside {c, skip}: up to three runs.
        let mut from = 0;
        for cut in [c, skip] {
            if cut >= dense_slots && cut < column.len() {
                largest = largest.max(largest_of(&sparse[from..cut - dense_slots]));
                from = cut - dense_slots + 1;
            }
        }
        largest = largest.max(largest_of(&sparse[from.min(sparse.len())..]));
        (largest, dense)
    }

    /// `a_ij −= Σ_k l_ik · row_k[j]` for every `i` outside `pivots` (and `j ≤ i`), where `l_i =
    /// a_i,pivots · inverse` and `row_k` are the pivot rows: the Schur complement of a 1×1 or 2×2
    /// pivot block. The pivots' columns must be loaded ([`Front::load`]). Calls `store(variable,
    /// l_i)` for every row with a nonzero `l_i`.
    pub fn eliminate<const P: usize>(
        &mut self,
        pivots: [usize; P],
        inverse: [[f64; P]; P],
        mut store: impl FnMut(usize, [f64; P]),
    ) {
        debug_assert_eq!(self.loaded, pivots, "eliminate the loaded pivots");
        let (s, len) = (self.stride, self.len());
        let rows = std::mem::take(&mut self.scratch);
        for i in 0..len {
            let coupling: [f64; P] = std::array::from_fn(|k| rows[k * len + i]);
            if coupling.iter().all(|&c| c == 0.0) || pivots.contains(&i) {
                continue;
            }
            let l: [f64; P] = std::array::from_fn(|k| (0..P).map(|m| coupling[m] * inverse[m][k]).sum());
            store(self.var[i], l);
            let row = &mut self.a[i * s..i * s + i + 1];
            if P == 2 {
                // Both pivot rows in one pass.
                let (first, second) = (&rows[..i + 1], &rows[len..len + i + 1]);
                for ((x, &r1), &r2) in row.iter_mut().zip(first).zip(second) {
                    *x -= l[0] * r1 + l[1] * r2;
                }
            } else {
                for (x, &r) in row.iter_mut().zip(&rows[..i + 1]) {
                    *x -= l[0] * r;
                }
            }
        }
        self.scratch = rows;
        self.loaded.clear();
        let mut gone = pivots;
        gone.sort_unstable();
        for &slot in gone.iter().rev() {
            self.remove(slot);
        }
    }

    /// Removes a slot: the last slot's row, column and variable move into it.
    fn remove(&mut self, slot: usize) {
        let s = self.stride;
        let gone = self.var[slot];
        if gone < self.dense {
            self.dense_first = false;
        }
        let last = self.len() - 1;
        if slot != last {
            // Row `slot` (up to the diagonal) from row `last`; column `slot` below the diagonal from
            // row `last` too (the entries `(i, last)` with `i < last` are stored as `(last, i)`).
            self.a.copy_within(last * s..last * s + slot, slot * s);
            self.a[slot * s + slot] = self.a[last * s + last];
            for i in slot + 1..last {
                self.a[i * s + slot] = self.a[last * s + i];
            }
            self.var[slot] = self.var[last];
            self.summed[slot] = self.summed[last];
            self.slot_of[self.var[slot]] = slot;
        }
        self.var.pop();
        self.summed.pop();
        self.slot_of[gone] = ABSENT;
    }
}
