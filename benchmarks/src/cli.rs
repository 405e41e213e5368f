//! Command-line arguments of the benchmark programs: a bad argument is a usage error (the
//! argument, what is allowed, exit code 2), never a panic.

use std::fmt::Display;
use std::str::FromStr;

/// Exit code of a usage error, as `spine`'s.
pub const USAGE_EXIT: i32 = 2;

/// Prints `error: {message}` and the usage line to stderr and exits with [`USAGE_EXIT`].
pub fn usage_error(message: impl Display, usage: &str) -> ! {
    eprintln!("error: {message}\nusage: {usage}");
    std::process::exit(USAGE_EXIT)
}

/// `text` parsed as a `T`, or why not: names the argument and what it must be.
pub fn parse<T: FromStr>(text: &str, what: &str) -> Result<T, String> {
    text.parse().map_err(|_| format!("{what}, got {text:?}"))
}

/// A chain size: a whole number of links, at least 2.
pub fn links(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 2 => Ok(n),
        _ => Err(format!("N must be a whole number of links, at least 2, got {text:?}")),
    }
}

/// A count of runs: a whole number, at least 1.
pub fn runs(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("a whole number of runs, at least 1, got {text:?}")),
    }
}

/// `NAME=VALUE` split at its first `=`, or why not.
pub fn name_value<'a>(text: &'a str, flag: &str) -> Result<(&'a str, &'a str), String> {
    text.split_once('=').ok_or_else(|| format!("{flag} expects NAME=VALUE, got {text:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_arguments_name_what_is_allowed() {
        assert_eq!(links("1000"), Ok(1000));
        assert!(links("1").unwrap_err().contains("at least 2"));
        assert!(links("--help").unwrap_err().contains("\"--help\""));
        assert_eq!(runs("3"), Ok(3));
        assert!(runs("0").unwrap_err().contains("at least 1"));
        assert_eq!(parse::<usize>("3", "--repeats=R: a whole number"), Ok(3));
        assert!(parse::<usize>("x", "--repeats=R: a whole number").unwrap_err().starts_with("--repeats"));
        assert_eq!(name_value("tol=1e-8", "--ipopt"), Ok(("tol", "1e-8")));
        assert!(name_value("tol", "--ipopt").unwrap_err().contains("NAME=VALUE"));
    }
}
