//! A table written as CSV beside `result.json`: typed columns (numbers, counts, labels), written
//! through the `csv` crate, and read by the Python package column by column (numpy arrays for
//! numbers and counts, lists of strings for labels) without parsing the text back.

/// One column's cells.
#[derive(Clone, Debug, PartialEq)]
pub enum Cells {
    /// Numbers in full precision (`{:e}`); `None` is an empty cell (a value that does not exist
    /// there, e.g. `θ0` of the end spring's row).
    Numbers(Vec<Option<f64>>),
    /// Whole numbers: indices (1-based), counts.
    Counts(Vec<usize>),
    /// Text: names, statuses, flags.
    Labels(Vec<String>),
}

impl Cells {
    fn len(&self) -> usize {
        match self {
            Self::Numbers(v) => v.len(),
            Self::Counts(v) => v.len(),
            Self::Labels(v) => v.len(),
        }
    }

    /// Row `i`'s cell as the CSV writes it (empty past the column's end).
    fn cell(&self, i: usize) -> String {
        match self {
            Self::Numbers(v) => v.get(i).copied().flatten().map_or(String::new(), |x| format!("{x:e}")),
            Self::Counts(v) => v.get(i).map_or(String::new(), ToString::to_string),
            Self::Labels(v) => v.get(i).cloned().unwrap_or_default(),
        }
    }
}

/// A named column.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    /// The header, with the unit in the name (`t_s`, `theta0_rad`).
    pub name: String,
    pub cells: Cells,
}

/// A table of columns, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    pub columns: Vec<Column>,
}

impl Table {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a column of cells.
    pub fn column(mut self, name: impl Into<String>, cells: Cells) -> Self {
        self.columns.push(Column { name: name.into(), cells });
        self
    }

    /// Adds a column of numbers.
    pub fn numbers(self, name: impl Into<String>, values: impl IntoIterator<Item = f64>) -> Self {
        self.column(name, Cells::Numbers(values.into_iter().map(Some).collect()))
    }

    /// Adds a column of numbers that may be missing (empty cells).
    pub fn optional(self, name: impl Into<String>, values: impl IntoIterator<Item = Option<f64>>) -> Self {
        self.column(name, Cells::Numbers(values.into_iter().collect()))
    }

    /// Adds a column of whole numbers.
    pub fn counts(self, name: impl Into<String>, values: impl IntoIterator<Item = usize>) -> Self {
        self.column(name, Cells::Counts(values.into_iter().collect()))
    }

    /// Adds a column of text.
    pub fn labels<S: ToString>(self, name: impl Into<String>, values: impl IntoIterator<Item = S>) -> Self {
        self.column(name, Cells::Labels(values.into_iter().map(|s| s.to_string()).collect()))
    }

    /// The number of rows (the longest column's length).
    pub fn rows(&self) -> usize {
        self.columns.iter().map(|c| c.cells.len()).max().unwrap_or(0)
    }

    /// Appends the rows of `other`, whose columns must have the same names in the same order.
    pub fn extend(&mut self, other: Table) {
        if self.columns.is_empty() {
            *self = other;
            return;
        }
        assert_eq!(
            self.columns.iter().map(|c| &c.name).collect::<Vec<_>>(),
            other.columns.iter().map(|c| &c.name).collect::<Vec<_>>(),
            "tables appended have the same columns"
        );
        for (mine, theirs) in self.columns.iter_mut().zip(other.columns) {
            match (&mut mine.cells, theirs.cells) {
                (Cells::Numbers(a), Cells::Numbers(b)) => a.extend(b),
                (Cells::Counts(a), Cells::Counts(b)) => a.extend(b),
                (Cells::Labels(a), Cells::Labels(b)) => a.extend(b),
                _ => panic!("column {} appended with cells of another type", mine.name),
            }
        }
    }

    /// The table as CSV (header line, then one line per row; `\n` ends every line).
    pub fn to_csv(&self) -> String {
        let mut writer = csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
        let header: Vec<&str> = self.columns.iter().map(|c| c.name.as_str()).collect();
        // Writing into memory cannot fail; a failure would be a bug of the csv crate.
        // Invariant: a `csv::Writer` over a `Vec<u8>` cannot fail to write, and every record has the
        // header's number of fields (one cell per column). The bytes are UTF-8 because every field is a
        // `String`.
        writer.write_record(&header).expect("CSV into memory");
        for i in 0..self.rows() {
            writer.write_record(self.columns.iter().map(|c| c.cells.cell(i))).expect("CSV into memory");
        }
        let bytes = writer.into_inner().expect("CSV into memory");
        String::from_utf8(bytes).expect("CSV of UTF-8 fields is UTF-8")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_written_in_full_precision_with_empty_missing_cells_and_quoted_labels() {
        let t = Table::new()
            .counts("index", 1..=3)
            .optional("theta0_rad", [Some(0.25), Some(-1.0 / 3.0), None])
            .numbers("stiffness_n_m_per_rad", [100.0, 1e4, 12.5])
            .labels("run", ["a", "b,c", "d"]);
        assert_eq!(
            t.to_csv(),
            "index,theta0_rad,stiffness_n_m_per_rad,run\n1,2.5e-1,1e2,a\n2,-3.333333333333333e-1,1e4,\"b,c\"\n3,,1.25e1,d\n"
        );
        let mut more = t.clone();
        more.extend(t);
        assert_eq!(more.rows(), 6);
    }
}
