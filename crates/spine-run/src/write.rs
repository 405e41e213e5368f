//! Writing a result's folder all or nothing: what the CLI's `--out` and the Python front's
//! `Result.write` do (the run path itself writes nothing).
//!
//! A run's folder is staged: every file is written into a fresh folder beside `--out`, created
//! exclusively under a name no other run uses (process id and time), with files created new (no
//! link followed), each synced, then the folder synced and swapped with `--out` in one step
//! (`renameat2` with `RENAME_EXCHANGE`), and the old folder removed. A reader sees the old complete
//! set of files or the new one, never a mix; a run that fails or is interrupted leaves `--out`
//! untouched (its staging folder is removed on failure; a killed run leaves only the hidden
//! staging folder); two runs into one `--out` each swap in a complete set.

use crate::files::{FileContent, OutputFile};
use crate::result::CaseResult;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Why a folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The output path cannot be a result folder (a file or a link): bad input.
    #[error("{0}")]
    Input(String),
    /// The file system refused (permissions, space), or a figure could not be drawn.
    #[error("{0}")]
    Io(String),
}

impl WriteError {
    /// Bad input (exit code 2), as opposed to a failure to write (exit code 1).
    pub fn is_input(&self) -> bool {
        matches!(self, Self::Input(_))
    }
}

/// A result folder: `result.json` and the files beside it, written as one new folder in place of
/// `dir`.
pub struct Folder {
    dir: PathBuf,
    deterministic: bool,
}

/// `result.json`'s text: the result with its wall times under `timings`, left out when
/// `deterministic` (then the same input gives the same bytes), pretty-printed, ending in a newline.
pub fn result_json(result: &CaseResult, deterministic: bool) -> String {
    let mut value = result.to_json();
    if deterministic {
        if let Some(map) = value.as_object_mut() {
            map.remove("timings");
        }
    }
    let mut text = serde_json::to_string_pretty(&value).expect("JSON values always serialise");
    text.push('\n');
    text
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

fn io_error(dir: &Path) -> impl Fn(std::io::Error) -> WriteError + '_ {
    move |e| WriteError::Io(format!("{}: cannot write: {e}", dir.display()))
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
    fn new(dir: &Path) -> Result<Self, WriteError> {
        let io = io_error(dir);
        if let Ok(meta) = std::fs::symlink_metadata(dir) {
            if !meta.is_dir() {
                return Err(WriteError::Input(format!(
                    "{}: the output must be a folder (it is a file or a symbolic link)",
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
    fn commit(mut self, dir: &Path) -> Result<(), WriteError> {
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

impl Folder {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self { dir: dir.to_path_buf(), deterministic }
    }

    /// Writes the result's files and `result.json` ([`result_json`]) as one new folder in place
    /// of `dir`. Returns the path of `result.json` and how many files are beside it.
    pub fn write_result(&self, result: &CaseResult) -> Result<(PathBuf, usize), WriteError> {
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
                    let svg = figure.to_svg().map_err(|e| WriteError::Io(format!("{name}.svg: {e}")))?;
                    create_new(&stage.path.join(format!("{name}.svg")), svg.as_bytes()).map_err(&io)?;
                    let png = stage.path.join(format!("{name}.png"));
                    figure.write_png(&png).map_err(|e| WriteError::Io(format!("{name}.png: {e}")))?;
                    sync(&png).map_err(&io)?;
                    let pdf = figure.to_pdf().map_err(|e| WriteError::Io(format!("{name}.pdf: {e}")))?;
                    create_new(&stage.path.join(format!("{name}.pdf")), &pdf).map_err(&io)?;
                    written += 3;
                }
                FileContent::Animation(animation) => {
                    let gif = animation.to_gif().map_err(|e| WriteError::Io(format!("{name}.gif: {e}")))?;
                    create_new(&stage.path.join(format!("{name}.gif")), &gif).map_err(&io)?;
                    written += 1;
                }
            }
        }
        let text = result_json(result, self.deterministic);
        create_new(&stage.path.join("result.json"), text.as_bytes()).map_err(&io)?;
        stage.commit(&self.dir)?;
        Ok((self.dir.join("result.json"), written))
    }

    /// Writes one text file into `dir` (created if needed) through a new file with a name no
    /// other run uses and a rename, so that `dir/name` is the old or the new text, never a part.
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), WriteError> {
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
