//! Writing results all or nothing, and printing to stdout without a panic when the reader has
//! gone (`spine … | head`).
//!
//! A run's folder is staged: every file is written into a fresh folder beside `--out`, created
//! exclusively under a name no other run uses (process id and time), with files created new (no
//! link followed), each synced, then the folder synced and swapped with `--out` in one step
//! (`renameat2` with `RENAME_EXCHANGE`), and the old folder removed. A reader sees the old complete
//! set of files or the new one, never a mix; a run that fails or is interrupted leaves `--out`
//! untouched (its staging folder is removed on failure; a killed run leaves only the hidden
//! staging folder); two runs into one `--out` each swap in a complete set.

use crate::Failure;
use spine_paper::run::{FileContent, OutputFile};
use spine_paper::CaseResult;
use std::io::Write as _;
use std::path::{Path, PathBuf};

pub struct Output {
    dir: PathBuf,
    deterministic: bool,
}

/// A fresh folder beside the output folder, removed unless committed.
struct Stage {
    path: PathBuf,
    committed: bool,
}

impl Drop for Stage {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

fn io_error(dir: &Path) -> impl Fn(std::io::Error) -> Failure + '_ {
    move |e| Failure::Other(format!("{}: cannot write: {e}", dir.display()))
}

/// A suffix no other run uses: the process id and the time in nanoseconds.
fn unique_suffix() -> String {
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    format!("{}-{nanos}", std::process::id())
}

/// Flushes a written file or folder to disk.
fn sync(path: &Path) -> std::io::Result<()> {
    std::fs::File::open(path)?.sync_all()
}

/// Writes `path` as a new file (never through an existing file or link) and syncs it.
fn create_new(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = std::fs::File::options().write(true).create_new(true).open(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

impl Stage {
    fn new(dir: &Path) -> Result<Self, Failure> {
        let io = io_error(dir);
        if let Ok(meta) = std::fs::symlink_metadata(dir) {
            if !meta.is_dir() {
                return Err(Failure::Input(format!(
                    "{}: --out must be a folder (it is a file or a symbolic link)",
                    dir.display()
                )));
            }
        }
        let parent = dir.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(&io)?;
        let name = dir.file_name().map_or("out".into(), |n| n.to_string_lossy().into_owned());
        let path = parent.join(format!(".{name}.staging-{}", unique_suffix()));
        std::fs::create_dir(&path).map_err(&io)?;
        Ok(Stage { path, committed: false })
    }

    /// Syncs the staged folder and puts it in place of `dir`.
    fn commit(mut self, dir: &Path) -> Result<(), Failure> {
        let io = io_error(dir);
        sync(&self.path).map_err(&io)?;
        // `dir` absent (or an empty folder): a plain rename. Otherwise swap the two folders in one
        // step and remove the old one, now at the staging path.
        if std::fs::rename(&self.path, dir).is_err() {
            rustix::fs::renameat_with(
                rustix::fs::CWD,
                &self.path,
                rustix::fs::CWD,
                dir,
                rustix::fs::RenameFlags::EXCHANGE,
            )
            .map_err(|e| io(e.into()))?;
            let _ = std::fs::remove_dir_all(&self.path);
        }
        self.committed = true;
        Ok(())
    }
}

impl Output {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self { dir: dir.to_path_buf(), deterministic }
    }

    /// Writes the result's files and `result.json` (its wall times under `timings`, dropped with
    /// `--deterministic`) as one new folder in place of `DIR`. Returns the path of `result.json`
    /// and how many files are beside it.
    pub fn write_result(&self, result: &CaseResult) -> Result<(PathBuf, usize), Failure> {
        let stage = Stage::new(&self.dir)?;
        let io = io_error(&self.dir);
        let mut written = 0;
        for OutputFile { name, content } in result.files() {
            match content {
                FileContent::Text(text) => {
                    create_new(&stage.path.join(&name), text.as_bytes()).map_err(&io)?;
                    written += 1;
                }
                FileContent::Figure(figure) => {
                    let svg = figure.to_svg().map_err(|e| Failure::Other(format!("{name}.svg: {e}")))?;
                    create_new(&stage.path.join(format!("{name}.svg")), svg.as_bytes()).map_err(&io)?;
                    let png = stage.path.join(format!("{name}.png"));
                    figure.write_png(&png).map_err(|e| Failure::Other(format!("{name}.png: {e}")))?;
                    sync(&png).map_err(&io)?;
                    written += 2;
                }
            }
        }
        let mut value = result.to_json();
        if self.deterministic {
            if let Some(map) = value.as_object_mut() {
                map.remove("timings");
            }
        }
        let mut text = serde_json::to_string_pretty(&value).expect("JSON values always serialise");
        text.push('\n');
        create_new(&stage.path.join("result.json"), text.as_bytes()).map_err(&io)?;
        stage.commit(&self.dir)?;
        Ok((self.dir.join("result.json"), written))
    }

    /// Writes one text file into `DIR` (created if needed) through a new file with a name no
    /// other run uses and a rename, so that `DIR/name` is the old or the new text, never a part.
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), Failure> {
        let io = io_error(&self.dir);
        std::fs::create_dir_all(&self.dir).map_err(&io)?;
        let tmp = self.dir.join(format!(".{name}.{}.tmp", unique_suffix()));
        create_new(&tmp, text.as_bytes()).map_err(&io)?;
        std::fs::rename(&tmp, self.dir.join(name)).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(e)
        })
    }
}

/// Prints `text` to stdout; a closed stdout (a pipe into `head`) is not an error: the run goes on
/// and its files are still written.
pub fn say(text: &str) {
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
