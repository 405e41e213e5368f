//! The front of the sweep: a small dense symmetric matrix over the variables that have entered and
//! are not yet eliminated, stored whole (both triangles) with a row stride that grows on demand.

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

#[derive(Debug)]
pub(crate) struct Front {
    stride: usize,
    /// Row-major `stride × stride`; only the leading `len × len` block is in use.
    a: Vec<f64>,
    /// The variable (new numbering) of each slot.
    pub var: Vec<usize>,
    /// The slot of each variable, or [`ABSENT`].
    pub slot_of: Vec<usize>,
    /// Whether the variable of each slot is fully summed.
    summed: Vec<bool>,
    /// The pivot rows during an elimination (kept to avoid an allocation per pivot).
    scratch: Vec<f64>,
}

impl Front {
    pub fn new(n: usize, capacity: usize) -> Self {
        let stride = capacity.max(4);
        Self {
            stride,
            a: vec![0.0; stride * stride],
            var: Vec::with_capacity(stride),
            summed: Vec::with_capacity(stride),
            slot_of: vec![ABSENT; n],
            scratch: Vec::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.var.len()
    }

    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.stride + j]
    }

    /// Row `i` of the front, `len` entries.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.a[i * self.stride..i * self.stride + self.len()]
    }

    /// Adds variable `v` with an empty row and column; returns its slot.
    pub fn push(&mut self, v: usize) -> usize {
        let slot = self.len();
        if slot == self.stride {
            self.grow();
        }
        let s = self.stride;
        for j in 0..=slot {
            self.a[slot * s + j] = 0.0;
            self.a[j * s + slot] = 0.0;
        }
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
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, value: f64) {
        let s = self.stride;
        self.a[i * s + j] += value;
        if i != j {
            self.a[j * s + i] += value;
        }
    }

    /// One pass over column `c` (read as row `c`: the front is stored whole) for the pivot tests:
    /// the largest `|a_ic|` over rows `i ≠ c` whose variable is not below `border` (the dense
    /// rows, numbered first) and its first row; the last row of largest `|a_ic|` among those whose
    /// variable is fully summed; and the largest entry in the dense rows. Rows in `skip` are left
    /// out.
    pub fn scan(&self, c: usize, skip: usize, border: usize) -> ColumnScan {
        let mut scan = ColumnScan { largest: 0.0, row: None, summed_largest: 0.0, summed_row: None, border: 0.0 };
        for (i, ((&x, &var), &summed)) in self.row(c).iter().zip(&self.var).zip(&self.summed).enumerate() {
            let v = x.abs();
            if var < border {
                scan.border = scan.border.max(v);
            } else if i != c && i != skip {
                if v > scan.largest {
                    scan.largest = v;
                    scan.row = Some(i);
                }
                if summed && (scan.summed_row.is_none() || v >= scan.summed_largest) {
                    scan.summed_largest = v;
                    scan.summed_row = Some(i);
                }
            }
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

    /// `a_ij −= Σ_k l_ik · row_k[j]` for every `i` outside `pivots`, where `l_i = a_i,pivots ·
    /// inverse` and `row_k` are the pivot rows: the Schur complement of a 1×1 or 2×2 pivot block.
    /// Calls `store(variable, l_i)` for every row with a nonzero `l_i`.
    pub fn eliminate<const P: usize>(
        &mut self,
        pivots: [usize; P],
        inverse: [[f64; P]; P],
        mut store: impl FnMut(usize, [f64; P]),
    ) {
        let (s, len) = (self.stride, self.len());
        let mut rows = std::mem::take(&mut self.scratch);
        rows.clear();
        for &p in &pivots {
            rows.extend_from_slice(self.row(p));
        }
        for i in 0..len {
            if pivots.contains(&i) {
                continue;
            }
            let coupling: [f64; P] = std::array::from_fn(|k| self.a[i * s + pivots[k]]);
            if coupling.iter().all(|&c| c == 0.0) {
                continue;
            }
            let l: [f64; P] = std::array::from_fn(|k| (0..P).map(|m| coupling[m] * inverse[m][k]).sum());
            store(self.var[i], l);
            let row = &mut self.a[i * s..i * s + len];
            for k in 0..P {
                let lk = l[k];
                for (x, &r) in row.iter_mut().zip(&rows[k * len..(k + 1) * len]) {
                    *x -= lk * r;
                }
            }
        }
        self.scratch = rows;
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
        let last = self.len() - 1;
        if slot != last {
            for j in 0..=last {
                self.a[slot * s + j] = self.a[last * s + j];
            }
            for i in 0..=last {
                self.a[i * s + slot] = self.a[i * s + last];
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
