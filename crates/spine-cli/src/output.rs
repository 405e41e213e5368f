//! Printing to stdout without a panic when the reader has gone (`spine … | head`), and the
//! result folder through `spine_run::write` with its errors as exit codes.

use crate::Failure;
use spine_run::write::{Folder, WriteError};
use spine_run::CaseResult;
use std::io::Write as _;
use std::path::{Path, PathBuf};

impl From<WriteError> for Failure {
    fn from(e: WriteError) -> Self {
        match e {
            WriteError::Input(m) => Failure::Input(m),
            WriteError::Io(m) => Failure::Other(m),
        }
    }
}

/// The `--out` folder of a run.
pub struct Output(Folder);

impl Output {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self(Folder::new(dir, deterministic))
    }

    /// `result.json` and the files beside it, all or nothing ([`Folder::write_result`]).
    pub fn write_result(&self, result: &CaseResult) -> Result<(PathBuf, usize), Failure> {
        Ok(self.0.write_result(result)?)
    }

    /// Whether the folder may be written, before any work ([`Folder::check`]): never the working
    /// directory, a folder holding an input, or a folder holding files the program did not write.
    pub fn check(&self, inputs: &[&Path]) -> Result<(), Failure> {
        Ok(self.0.check(inputs)?)
    }

    /// Files as one new folder, all or nothing ([`Folder::write_files`]).
    pub fn write_files(&self, files: &[(&str, &[u8])]) -> Result<(), Failure> {
        Ok(self.0.write_files(files)?)
    }

    /// One text file, old or new, never a part, and never over a file the program did not write
    /// ([`Folder::write_text`]).
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), Failure> {
        Ok(self.0.write_text(name, text)?)
    }

    /// Whether [`Output::write_text`] may write `name` ([`Folder::check_text`]).
    pub fn check_text(&self, name: &str) -> Result<(), Failure> {
        Ok(self.0.check_text(name)?)
    }
}

/// Prints `text` to stdout as a person reads it ([`spine_check::readable`]: long numbers in short
/// form, control and bidirectional characters escaped); a closed stdout (a pipe into `head`) is
/// not an error: the run goes on and its files are still written.
pub fn say(text: &str) {
    let _ = std::io::stdout().lock().write_all(spine_check::readable(text).as_bytes());
}
