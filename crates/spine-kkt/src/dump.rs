//! The text form of a recorded KKT system (`SPINE_KKT_DUMP`, `SPINE_KKT_DUMP_BAD`): the order,
//! then Pardiso's 1-based CSR arrays `ia`, `ja`, `a` of the upper triangle, then optionally a
//! right-hand side, one bracketed list per line. Fixtures of the tests and benchmarks are in this
//! form.

use crate::{KktError, Structure};

/// A recorded system: the matrix in Pardiso's arrays and, when recorded, a right-hand side.
#[derive(Clone, Debug, PartialEq)]
pub struct Dump {
    pub n: usize,
    pub ia: Vec<i32>,
    pub ja: Vec<i32>,
    pub a: Vec<f64>,
    pub rhs: Option<Vec<f64>>,
}

impl Dump {
    /// Parses the text form.
    pub fn parse(text: &str) -> Result<Self, KktError> {
        let mut lines = text.lines();
        let mut next = |what: &str| lines.next().ok_or_else(|| KktError::Input(format!("the dump has no {what} line")));
        let n = next("order")?.trim().parse().map_err(|e| KktError::Input(format!("the order: {e}")))?;
        let ia = list(next("ia")?, "ia")?;
        let ja = list(next("ja")?, "ja")?;
        let a = list(next("a")?, "a")?;
        let rhs = lines.next().filter(|l| !l.trim().is_empty()).map(|l| list(l, "right-hand side")).transpose()?;
        Ok(Self { n, ia, ja, a, rhs })
    }

    /// The text form (what [`Dump::parse`] reads).
    pub fn format(&self) -> String {
        let mut text = format!("{}\n{:?}\n{:?}\n{:?}\n", self.n, self.ia, self.ja, self.a);
        if let Some(rhs) = &self.rhs {
            text.push_str(&format!("{rhs:?}\n"));
        }
        text
    }

    /// The structure of the matrix.
    pub fn structure(&self) -> Result<Structure, KktError> {
        Structure::from_one_based(self.n, &self.ia, &self.ja)
    }
}

fn list<T: std::str::FromStr>(line: &str, what: &str) -> Result<Vec<T>, KktError>
where
    T::Err: std::fmt::Display,
{
    line.trim()
        .trim_start_matches('[')
        .trim_end_matches(']')
        .split(',')
        .filter(|s| !s.trim().is_empty())
        .map(|s| s.trim().parse().map_err(|e| KktError::Input(format!("{what}: `{}`: {e}", s.trim()))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_text_form_round_trips_and_names_what_is_missing() {
        let dump = Dump { n: 2, ia: vec![1, 3, 3], ja: vec![1, 2], a: vec![2.0, 1.0], rhs: Some(vec![3.0, 1.0]) };
        assert_eq!(Dump::parse(&dump.format()).unwrap(), dump);
        assert_eq!(dump.structure().unwrap().stored(), 2);
        let no_rhs = Dump { rhs: None, ..dump };
        assert_eq!(Dump::parse(&no_rhs.format()).unwrap(), no_rhs);
        assert!(matches!(Dump::parse("2\n[1, 3, 3]\n"), Err(KktError::Input(m)) if m.contains("ja")));
        assert!(matches!(Dump::parse("2\n[1, x]\n[1]\n[1.0]\n"), Err(KktError::Input(m)) if m.contains("ia")));
    }
}
