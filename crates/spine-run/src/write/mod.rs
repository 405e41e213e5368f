//! Writing a result's folder all or nothing, and never at the cost of a file the program did not
//! write: what the CLI's `--out` and the Python front's `Result.write` do (the run path itself
//! writes nothing).
//!
//! **Which folders may be replaced.** Every folder the program writes holds a marker,
//! [`MARKER`], listing the files it wrote there. An existing `--out` is replaced only when it is
//! empty or holds its marker and nothing but the files the marker lists; a folder holding anything
//! else (a user's notes, the case file, sub-folders), a file, a symbolic link, the working
//! directory, a folder holding it or the run's input files, is refused as bad input (exit code 2)
//! — checked by [`Folder::check`] before any computation and again just before the swap.
//!
//! **All or nothing.** Every file is written into a fresh folder beside `--out`, created
//! exclusively under a name no other run uses (process id and time), with files created new (no
//! link followed), each synced, then the folder synced and swapped with `--out` in one step
//! (`renameat2` with `RENAME_EXCHANGE`). The old folder's listed files are then removed one by one
//! and the folder itself only if that left it empty (never `remove_dir_all` on a folder the run
//! did not make). A reader sees the old complete set of files or the new one, never a mix; a run
//! that fails or is interrupted leaves `--out` untouched.

mod existing;

use crate::files::{FileContent, OutputFile};
use crate::result::CaseResult;
use existing::{existing_ancestor, marker_text, name_of, parent_of, read_marker, refuse, shown, writable, Existing};
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The file in every folder the program writes that lists the files it wrote there, one name per
/// line after a header line.
pub const MARKER: &str = ".spine-output";

/// The marker's first line.
const MARKER_HEADER: &str =
    "# written by spine: the files below; spine replaces them, and this folder, only while it holds nothing else";

/// Why a folder could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The output path cannot be a result folder (a file, a link, a folder with a user's files,
    /// the working directory or a folder holding an input): bad input.
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
    // Invariant: a `serde_json::Value` always serialises.
    let mut text = serde_json::to_string_pretty(&value).expect("JSON values always serialise");
    text.push('\n');
    text
}

impl Folder {
    pub fn new(dir: &Path, deterministic: bool) -> Self {
        Self { dir: dir.to_path_buf(), deterministic }
    }

    /// Whether this folder may be written as a result folder, before any work: not a file or a
    /// link, not `.`/`..`, not the working directory, a folder holding it or one of `inputs`
    /// (the case file, shards); empty or holding only what an earlier run wrote ([`MARKER`]); its
    /// nearest existing ancestor a folder this process can write into.
    pub fn check(&self, inputs: &[&Path]) -> Result<(), WriteError> {
        self.existing(inputs).map(|_| ())
    }

    /// Writes the result's files and `result.json` ([`result_json`]) as one new folder in place
    /// of `dir`. Returns the path of `result.json` and how many files are beside it.
    pub fn write_result(&self, result: &CaseResult) -> Result<(PathBuf, usize), WriteError> {
        self.check(&[])?;
        let stage = Stage::new(&self.dir)?;
        let io = io_error(&self.dir);
        let mut written = Vec::new();
        for OutputFile { name, content } in result.files() {
            match content {
                FileContent::Text(text) => {
                    stage.create(&name, text.as_bytes()).map_err(&io)?;
                    written.push(name);
                }
                FileContent::Table(table) => {
                    stage.create(&name, table.to_csv().as_bytes()).map_err(&io)?;
                    written.push(name);
                }
                FileContent::Figure(figure) => {
                    let svg = figure.to_svg().map_err(|e| WriteError::Io(format!("{name}.svg: {e}")))?;
                    stage.create(&format!("{name}.svg"), svg.as_bytes()).map_err(&io)?;
                    let png = stage.path.join(format!("{name}.png"));
                    figure.write_png(&png).map_err(|e| WriteError::Io(format!("{name}.png: {e}")))?;
                    sync(&png).map_err(&io)?;
                    let pdf = figure.to_pdf().map_err(|e| WriteError::Io(format!("{name}.pdf: {e}")))?;
                    stage.create(&format!("{name}.pdf"), &pdf).map_err(&io)?;
                    written.extend(["svg", "png", "pdf"].map(|ext| format!("{name}.{ext}")));
                }
                FileContent::Animation(animation) => {
                    let gif = animation.to_gif().map_err(|e| WriteError::Io(format!("{name}.gif: {e}")))?;
                    stage.create(&format!("{name}.gif"), &gif).map_err(&io)?;
                    written.push(format!("{name}.gif"));
                }
            }
        }
        let text = result_json(result, self.deterministic);
        stage.create("result.json", text.as_bytes()).map_err(&io)?;
        let beside = written.len();
        written.push("result.json".into());
        self.commit(stage, written)?;
        Ok((self.dir.join("result.json"), beside))
    }

    /// Writes `files` (name, bytes) as one new folder in place of `dir`, as
    /// [`Folder::write_result`] does (`spine design --shard` writes `shard.json` this way).
    pub fn write_files(&self, files: &[(&str, &[u8])]) -> Result<(), WriteError> {
        self.check(&[])?;
        let stage = Stage::new(&self.dir)?;
        let io = io_error(&self.dir);
        for (name, bytes) in files {
            stage.create(name, bytes).map_err(&io)?;
        }
        self.commit(stage, files.iter().map(|(n, _)| n.to_string()).collect())
    }

    /// Writes the marker listing `written` into the stage and puts the stage in place of `dir`;
    /// then removes the old folder's listed files, and the old folder if that emptied it.
    fn commit(&self, mut stage: Stage, mut written: Vec<String>) -> Result<(), WriteError> {
        let dir = &self.dir;
        let io = io_error(dir);
        written.sort();
        stage.create(MARKER, marker_text(&written).as_bytes()).map_err(&io)?;
        sync(&stage.path).map_err(&io)?;
        // Checked again just before the swap: a user's file may have arrived during the run.
        match self.existing(&[])? {
            Existing::Absent | Existing::Empty => {
                std::fs::rename(&stage.path, dir).map_err(&io)?;
                stage.committed = true;
            }
            Existing::Ours => {
                rustix::fs::renameat_with(
                    rustix::fs::CWD,
                    &stage.path,
                    rustix::fs::CWD,
                    dir,
                    rustix::fs::RenameFlags::EXCHANGE,
                )
                .map_err(|e| io(e.into()))?;
                // The old folder is now at the staging path (never to be removed as a whole):
                // only what its own marker lists goes (read again: another run may have swapped
                // in its folder since the check).
                stage.committed = true;
                let old = read_marker(&stage.path).unwrap_or_default();
                for name in old.iter().map(String::as_str).chain([MARKER]) {
                    let plain = !name.contains('/') && name != "." && name != "..";
                    if plain && std::fs::symlink_metadata(stage.path.join(name)).is_ok_and(|m| m.is_file()) {
                        let _ = std::fs::remove_file(stage.path.join(name));
                    }
                }
                if std::fs::remove_dir(&stage.path).is_err() {
                    // Something arrived between the check and the swap: kept, under a visible name.
                    let kept = stage.path.with_file_name(format!("{}.kept-{}", name_of(dir), unique_suffix()));
                    let _ = std::fs::rename(&stage.path, kept);
                }
            }
        }
        Ok(())
    }

    /// Writes one text file into `dir` (created if needed; a folder of others' files too, e.g.
    /// `results/REPORT.md` beside the result folders) through a new file with a name no other run
    /// uses and a rename, so that `dir/name` is the old or the new text, never a part. An existing
    /// `dir/name` is replaced only if the folder's [`MARKER`] lists it (an earlier run wrote it).
    pub fn write_text(&self, name: &str, text: &str) -> Result<(), WriteError> {
        self.check_text(name)?;
        let io = io_error(&self.dir);
        std::fs::create_dir_all(&self.dir).map_err(&io)?;
        let mut listed = read_marker(&self.dir).unwrap_or_default();
        if !listed.iter().any(|n| n == name) {
            listed.push(name.to_string());
            listed.sort();
            self.replace_file(MARKER, &marker_text(&listed))?;
        }
        self.replace_file(name, text)
    }

    /// Whether [`Folder::write_text`] may write `dir/name`: `dir` a folder (or absent) that is not
    /// a link, `dir/name` absent or listed in the folder's marker.
    pub fn check_text(&self, name: &str) -> Result<(), WriteError> {
        let dir = &self.dir;
        match std::fs::symlink_metadata(dir) {
            Ok(meta) if meta.file_type().is_symlink() && !std::fs::metadata(dir).is_ok_and(|m| m.is_dir()) => {
                return Err(refuse(dir, "is a link to no folder"));
            }
            Ok(meta) if !meta.file_type().is_symlink() && !meta.is_dir() => {
                return Err(refuse(dir, "is a file; the output must be a folder"))
            }
            _ => {}
        }
        let path = dir.join(name);
        if std::fs::symlink_metadata(&path).is_ok() {
            let listed = read_marker(dir).unwrap_or_default();
            if !listed.iter().any(|n| n == name) || !std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
                return Err(WriteError::Input(format!(
                    "{}: a file this program did not write; move it or give another folder",
                    shown(&path)
                )));
            }
        }
        writable(dir, &existing_ancestor(dir))
    }

    fn replace_file(&self, name: &str, text: &str) -> Result<(), WriteError> {
        let io = io_error(&self.dir);
        let tmp = self.dir.join(format!(".{name}.{}.tmp", unique_suffix()));
        create_new(&tmp, text.as_bytes()).map_err(&io)?;
        std::fs::rename(&tmp, self.dir.join(name)).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io(e)
        })
    }
}

/// A fresh folder beside the output folder, made by this run (created exclusively), removed
/// unless committed.
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
    move |e| WriteError::Io(format!("{}: cannot write: {e}", shown(dir)))
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
        let parent = parent_of(dir);
        std::fs::create_dir_all(&parent).map_err(&io)?;
        let path = parent.join(format!(".{}.staging-{}", name_of(dir), unique_suffix()));
        std::fs::create_dir(&path).map_err(&io)?;
        Ok(Stage { path, committed: false })
    }

    fn create(&self, name: &str, bytes: &[u8]) -> std::io::Result<()> {
        create_new(&self.path.join(name), bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("spine-write-{tag}-{}", unique_suffix()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn files(dir: &Path) -> Vec<String> {
        let mut names: Vec<_> =
            std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }

    #[test]
    fn a_folder_it_wrote_is_replaced_and_nothing_else_is() {
        let root = tmp("replace");
        let out = root.join("out");
        let folder = Folder::new(&out, true);
        folder.write_files(&[("a.txt", b"1"), ("b.txt", b"2")]).unwrap();
        assert_eq!(files(&out), [MARKER, "a.txt", "b.txt"]);
        // Replaced: b.txt goes (listed), c.txt comes.
        folder.write_files(&[("a.txt", b"3"), ("c.txt", b"4")]).unwrap();
        assert_eq!(files(&out), [MARKER, "a.txt", "c.txt"]);
        assert_eq!(std::fs::read(out.join("a.txt")).unwrap(), b"3");
        // A user's file in it: refused, nothing touched.
        std::fs::write(out.join("notes.txt"), "mine").unwrap();
        let e = folder.write_files(&[("a.txt", b"5")]).unwrap_err();
        assert!(e.is_input() && e.to_string().contains("notes.txt"), "{e}");
        assert_eq!(files(&out), [MARKER, "a.txt", "c.txt", "notes.txt"]);
        assert_eq!(std::fs::read(out.join("a.txt")).unwrap(), b"3");
        // No staging folder left behind.
        assert_eq!(files(&root), ["out"]);
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn folders_it_did_not_write_are_refused() {
        let root = tmp("refuse");
        // A folder of a user's files.
        let user = root.join("user");
        std::fs::create_dir_all(user.join("sub")).unwrap();
        std::fs::write(user.join("case.json"), "{}").unwrap();
        let e = Folder::new(&user, true).write_files(&[("x", b"")]).unwrap_err();
        assert!(e.is_input() && e.to_string().contains("did not write"), "{e}");
        assert_eq!(files(&user), ["case.json", "sub"]);
        // A forged marker does not cover a sub-folder.
        std::fs::write(user.join(MARKER), marker_text(&["case.json".into(), "sub".into()])).unwrap();
        let e = Folder::new(&user, true).write_files(&[("x", b"")]).unwrap_err();
        assert!(e.is_input() && e.to_string().contains("sub"), "{e}");
        assert!(user.join("sub").is_dir());
        // A file and a link.
        std::fs::write(root.join("file"), "x").unwrap();
        assert!(Folder::new(&root.join("file"), true).check(&[]).unwrap_err().is_input());
        std::os::unix::fs::symlink(&user, root.join("link")).unwrap();
        assert!(Folder::new(&root.join("link"), true).check(&[]).unwrap_err().is_input());
        // An input inside, or the folder holding an input.
        let out = root.join("out");
        Folder::new(&out, true).write_files(&[("a", b"")]).unwrap();
        let e = Folder::new(&root, true).check(&[&out.join("a")]).unwrap_err();
        assert!(e.to_string().contains("holds the input"), "{e}");
        assert!(Folder::new(&out, true).check(&[&out.join("a")]).is_err());
        // `.`, `..`, `/` and the working directory (and its ancestors).
        for p in [".", "..", "/", ""] {
            assert!(Folder::new(Path::new(p), true).check(&[]).unwrap_err().is_input(), "{p}");
        }
        let cwd = std::env::current_dir().unwrap();
        assert!(Folder::new(&cwd, true).check(&[]).unwrap_err().to_string().contains("working directory"));
        assert!(Folder::new(cwd.parent().unwrap(), true).check(&[]).is_err());
        // An empty folder is accepted (nothing in it is lost).
        let empty = root.join("empty");
        std::fs::create_dir(&empty).unwrap();
        Folder::new(&empty, true).write_files(&[("a", b"1")]).unwrap();
        assert_eq!(files(&empty), [MARKER, "a"]);
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn text_files_replace_only_what_the_program_wrote() {
        let root = tmp("text");
        let folder = Folder::new(&root, false);
        folder.write_text("REPORT.md", "1").unwrap();
        folder.write_text("REPORT.md", "2").unwrap();
        assert_eq!(std::fs::read_to_string(root.join("REPORT.md")).unwrap(), "2");
        std::fs::write(root.join("mine.md"), "user").unwrap();
        let e = folder.write_text("mine.md", "3").unwrap_err();
        assert!(e.is_input(), "{e}");
        assert_eq!(std::fs::read_to_string(root.join("mine.md")).unwrap(), "user");
        std::fs::remove_dir_all(&root).unwrap();
    }
}
