//! A symmetric sparse matrix stored by one triangle in compressed rows: the form in which Ipopt
//! hands its KKT matrix to Pardiso (the upper triangle, 1-based; here 0-based).

use crate::KktError;

/// The structure of a symmetric `n × n` matrix: for each row `r`, the columns `col[row_start[r] ..
/// row_start[r + 1]]` of its stored entries. Each stored entry `(r, c)` stands for both `(r, c)`
/// and `(c, r)`; the values live apart (one slice per numerical factorisation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Structure {
    n: usize,
    row_start: Vec<usize>,
    col: Vec<usize>,
}

impl Structure {
    /// Checks and takes a 0-based compressed-row structure.
    pub fn new(n: usize, row_start: Vec<usize>, col: Vec<usize>) -> Result<Self, KktError> {
        if row_start.len() != n + 1 || row_start[0] != 0 {
            return Err(KktError::Input(format!(
                "row starts: {} entries for n = {n}, first must be 0",
                row_start.len()
            )));
        }
        if row_start.windows(2).any(|w| w[1] < w[0]) || row_start[n] != col.len() {
            return Err(KktError::Input("row starts must be non-decreasing and end at the number of entries".into()));
        }
        if let Some(&c) = col.iter().find(|&&c| c >= n) {
            return Err(KktError::Input(format!("column {c} outside a matrix of order {n}")));
        }
        Ok(Self { n, row_start, col })
    }

    /// Takes Pardiso's 1-based compressed rows (`ia` of length `n + 1`, `ja` of length `ia[n] − 1`).
    pub fn from_one_based(n: usize, ia: &[i32], ja: &[i32]) -> Result<Self, KktError> {
        let to_index = |v: i32, what: &str| {
            usize::try_from(v - 1).map_err(|_| KktError::Input(format!("{what} entry {v} is not a 1-based index")))
        };
        let row_start = ia.iter().map(|&v| to_index(v, "ia")).collect::<Result<Vec<_>, _>>()?;
        let col = ja.iter().map(|&v| to_index(v, "ja")).collect::<Result<Vec<_>, _>>()?;
        Self::new(n, row_start, col)
    }

    /// Builds the structure of a list of `(row, column)` entries of one triangle, row by row in
    /// the given order; returns it with, for each input entry, its position in the stored order.
    pub fn from_entries(n: usize, entries: &[(usize, usize)]) -> Result<(Self, Vec<usize>), KktError> {
        let mut count = vec![0usize; n + 1];
        for &(r, c) in entries {
            if r >= n || c >= n {
                return Err(KktError::Input(format!("entry ({r}, {c}) outside a matrix of order {n}")));
            }
            count[r + 1] += 1;
        }
        for r in 0..n {
            count[r + 1] += count[r];
        }
        let mut next = count.clone();
        let mut col = vec![0; entries.len()];
        let mut position = vec![0; entries.len()];
        for (e, &(r, c)) in entries.iter().enumerate() {
            position[e] = next[r];
            col[next[r]] = c;
            next[r] += 1;
        }
        Ok((Self::new(n, count, col)?, position))
    }

    /// The order `n`.
    pub fn order(&self) -> usize {
        self.n
    }

    /// The number of stored entries.
    pub fn stored(&self) -> usize {
        self.col.len()
    }

    /// The stored entries as `(row, column, position in the value slice)`.
    /// The stored entries of row `r`: their positions and columns.
    pub fn row(&self, r: usize) -> (std::ops::Range<usize>, &[usize]) {
        let range = self.row_start[r]..self.row_start[r + 1];
        (range.clone(), &self.col[range])
    }

    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
        (0..self.n).flat_map(move |r| (self.row_start[r]..self.row_start[r + 1]).map(move |e| (r, self.col[e], e)))
    }

    /// `y = A x` for the symmetric matrix with these `values`.
    pub fn multiply(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for r in 0..self.n {
            // Row `r`'s own terms are added to what the rows above put into `y[r]`, in the order of
            // the entries, as an entry-by-entry loop would.
            let (xr, mut sum) = (x[r], y[r]);
            for e in self.row_start[r]..self.row_start[r + 1] {
                let c = self.col[e];
                sum += values[e] * x[c];
                if r != c {
                    y[c] += values[e] * xr;
                }
            }
            y[r] = sum;
        }
    }

    /// `y = A x` and `magnitude = |A| |x|` (the scale of a residual's terms, for the componentwise
    /// backward error) in one pass.
    pub fn multiply_with_magnitude(&self, values: &[f64], x: &[f64], y: &mut [f64], magnitude: &mut [f64]) {
        y.fill(0.0);
        magnitude.fill(0.0);
        for r in 0..self.n {
            let (xr, mut sum, mut size) = (x[r], y[r], magnitude[r]);
            for e in self.row_start[r]..self.row_start[r + 1] {
                let c = self.col[e];
                let (forward, backward) = (values[e] * x[c], values[e] * xr);
                sum += forward;
                size += forward.abs();
                if r != c {
                    y[c] += backward;
                    magnitude[c] += backward.abs();
                }
            }
            y[r] = sum;
            magnitude[r] = size;
        }
    }

    /// The neighbours of every node in the graph of the matrix (both directions, no self loops, no
    /// repeats), sorted.
    pub fn adjacency(&self) -> Vec<Vec<usize>> {
        let mut adjacent = vec![Vec::new(); self.n];
        for (r, c, _) in self.entries() {
            if r != c {
                adjacent[r].push(c);
                adjacent[c].push(r);
            }
        }
        for list in &mut adjacent {
            list.sort_unstable();
            list.dedup();
        }
        adjacent
    }
}
