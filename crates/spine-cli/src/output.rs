//! Writing results: `DIR/result.json` and CSV files, each written whole or not at all.

use crate::Failure;
use serde_json::Value;
use std::path::{Path, PathBuf};

pub struct Output {
    dir: PathBuf,
    pub deterministic: bool,
}

impl Output {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self { dir: dir.to_path_buf(), deterministic }
    }

    /// Writes `value` as pretty JSON to `DIR/name` through a temporary file and a rename.
    /// Timings live under the top-level key `timings`, dropped with `--deterministic`.
    pub fn write_json(&self, name: &str, mut value: Value) -> Result<PathBuf, Failure> {
        if self.deterministic {
            if let Value::Object(map) = &mut value {
                map.remove("timings");
            }
        }
        let mut text = serde_json::to_string_pretty(&value).expect("JSON values always serialise");
        text.push('\n');
        self.write_file(name, &text)
    }

    /// Writes a text file (CSV) to `DIR/name` the same way.
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), Failure> {
        self.write_file(name, text).map(|_| ())
    }

    /// Writes `DIR/stem.svg` and `DIR/stem.png` (each through a temporary file and a rename).
    pub fn write_figure(&self, stem: &str, figure: &spine_plot::Figure) -> Result<(), Failure> {
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
