//! Writing results: `DIR/result.json` and the files beside it, each written whole or not at all;
//! and printing to stdout without a panic when the reader has gone (`spine … | head`).

use crate::Failure;
use spine_paper::run::{FileContent, OutputFile};
use spine_paper::CaseResult;
use std::io::Write as _;
use std::path::{Path, PathBuf};

pub struct Output {
    dir: PathBuf,
    deterministic: bool,
}

impl Output {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self { dir: dir.to_path_buf(), deterministic }
    }

    /// Writes the result's files, then `result.json` (its wall times under `timings`, dropped with
    /// `--deterministic`). Returns the path of `result.json` and how many files are beside it.
    pub fn write_result(&self, result: &CaseResult) -> Result<(PathBuf, usize), Failure> {
        let mut written = 0;
        for OutputFile { name, content } in result.files() {
            written += match content {
                FileContent::Text(text) => self.write_file(&name, &text).map(|_| 1)?,
                FileContent::Figure(figure) => self.write_figure(&name, &figure).map(|_| 2)?,
            };
        }
        let mut value = result.to_json();
        if self.deterministic {
            if let Some(map) = value.as_object_mut() {
                map.remove("timings");
            }
        }
        let mut text = serde_json::to_string_pretty(&value).expect("JSON values always serialise");
        text.push('\n');
        Ok((self.write_file("result.json", &text)?, written))
    }

    /// Writes a text file to `DIR/name` through a temporary file and a rename.
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), Failure> {
        self.write_file(name, text).map(|_| ())
    }

    /// Writes `DIR/stem.svg` and `DIR/stem.png` (each through a temporary file and a rename).
    fn write_figure(&self, stem: &str, figure: &spine_plot::Figure) -> Result<(), Failure> {
        let svg = figure.to_svg().map_err(|e| Failure::Other(format!("{stem}.svg: {e}")))?;
        self.write_file(&format!("{stem}.svg"), &svg)?;
        let tmp = self.dir.join(format!(".{stem}.png.tmp.png"));
        figure.write_png(&tmp).map_err(|e| Failure::Other(format!("{stem}.png: {e}")))?;
        std::fs::rename(&tmp, self.dir.join(format!("{stem}.png")))
            .map_err(|e| Failure::Other(format!("{}: cannot write: {e}", self.dir.display())))
    }

    fn write_file(&self, name: &str, text: &str) -> Result<PathBuf, Failure> {
        let io = |e: std::io::Error| Failure::Other(format!("{}: cannot write: {e}", self.dir.display()));
        std::fs::create_dir_all(&self.dir).map_err(io)?;
        let target = self.dir.join(name);
        let tmp = self.dir.join(format!(".{name}.tmp"));
        std::fs::write(&tmp, text).map_err(io)?;
        std::fs::rename(&tmp, &target).map_err(io)?;
        Ok(target)
    }
}

/// Prints `text` to stdout; a closed stdout (a pipe into `head`) is not an error: the run goes on
/// and its files are still written.
pub fn say(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
