//! Ipopt options as an ordered list of `name = value` pairs.

use std::fmt;

/// One option value; Ipopt distinguishes strings, numbers and integers.
#[derive(Clone, Debug, PartialEq)]
pub enum OptionValue {
    Str(String),
    Num(f64),
    Int(i64),
}

impl fmt::Display for OptionValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OptionValue::Str(s) => write!(f, "\"{s}\""),
            OptionValue::Num(x) => write!(f, "{x:e}"),
            OptionValue::Int(i) => write!(f, "{i}"),
        }
    }
}

/// Options in the order they are given; a later value of a name overrides an earlier one.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Options {
    entries: Vec<(String, OptionValue)>,
}

impl Options {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or overrides) a string option, e.g. `("mu_strategy", "adaptive")`.
    pub fn string(self, name: &str, value: &str) -> Self {
        self.with(name, OptionValue::Str(value.to_owned()))
    }

    /// Adds (or overrides) a numeric option, e.g. `("tol", 1e-9)`.
    pub fn number(self, name: &str, value: f64) -> Self {
        self.with(name, OptionValue::Num(value))
    }

    /// Adds (or overrides) an integer option, e.g. `("max_iter", 3000)`.
    pub fn integer(self, name: &str, value: i64) -> Self {
        self.with(name, OptionValue::Int(value))
    }

    /// Adds (or overrides) an option.
    pub fn with(mut self, name: &str, value: OptionValue) -> Self {
        self.set(name, value);
        self
    }

    /// Sets an option in place.
    pub fn set(&mut self, name: &str, value: OptionValue) {
        match self.entries.iter_mut().find(|(n, _)| n == name) {
            Some(entry) => entry.1 = value,
            None => self.entries.push((name.to_owned(), value)),
        }
    }

    /// Adds every option of `other`, overriding equal names.
    pub fn extend(&mut self, other: &Options) {
        for (name, value) in &other.entries {
            self.set(name, value.clone());
        }
    }

    /// The value of an option, if set.
    pub fn get(&self, name: &str) -> Option<&OptionValue> {
        self.entries.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }

    pub fn iter(&self) -> impl Iterator<Item = (&str, &OptionValue)> {
        self.entries.iter().map(|(n, v)| (n.as_str(), v))
    }
}
