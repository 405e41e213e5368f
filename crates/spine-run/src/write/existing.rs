//! Whether an existing output folder may be replaced: what it holds against its marker, where it
//! is (never the working directory or a folder holding the run's inputs), and whether its parent
//! can be written.

use super::{Folder, WriteError, MARKER, MARKER_HEADER};
use std::path::{Path, PathBuf};

/// A path as a user reads it in a one-line message: shortened, control characters escaped.
pub(super) fn shown(path: &Path) -> String {
    spine_check::shown(&path.display().to_string())
}

pub(super) fn refuse(dir: &Path, why: impl std::fmt::Display) -> WriteError {
    WriteError::Input(format!("--out {}: {why}", shown(dir)))
}

/// The names a marker lists (`None`: no marker, or not one of ours).
pub(super) fn read_marker(dir: &Path) -> Option<Vec<String>> {
    let meta = std::fs::symlink_metadata(dir.join(MARKER)).ok()?;
    if !meta.is_file() || meta.len() > 1 << 20 {
        return None;
    }
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    let mut lines = text.lines();
    (lines.next()? == MARKER_HEADER).then(|| lines.filter(|l| !l.is_empty()).map(String::from).collect())
}

pub(super) fn marker_text(names: &[String]) -> String {
    let mut text = format!("{MARKER_HEADER}\n");
    for name in names {
        text.push_str(name);
        text.push('\n');
    }
    text
}

/// `1 entry`, `3 entries`.
pub(super) fn entries(n: usize) -> String {
    if n == 1 {
        "1 entry".into()
    } else {
        format!("{n} entries")
    }
}

/// What an existing output folder holds, as far as replacing it goes.
pub(super) enum Existing {
    /// Nothing at the path.
    Absent,
    /// An empty folder (a plain rename replaces it: nothing is lost).
    Empty,
    /// A folder the program wrote, holding only the files its marker lists.
    Ours,
}

/// The absolute form of `path` with every link resolved, also for a path whose last components do
/// not exist yet (resolved up to the deepest existing ancestor).
pub(super) fn resolved(path: &Path) -> Option<PathBuf> {
    let absolute = if path.is_absolute() { path.to_path_buf() } else { std::env::current_dir().ok()?.join(path) };
    let mut rest = Vec::new();
    let mut head = absolute.as_path();
    loop {
        if let Ok(real) = head.canonicalize() {
            return Some(rest.iter().rev().fold(real, |p, c| p.join(c)));
        }
        rest.push(head.file_name()?.to_os_string());
        head = head.parent()?;
    }
}

/// The folder `dir` sits in (`.` for a bare name).
pub(super) fn parent_of(dir: &Path) -> PathBuf {
    dir.parent().filter(|p| !p.as_os_str().is_empty()).map_or(PathBuf::from("."), Path::to_path_buf)
}

/// `dir`'s last component, for the names of its staging folder and of a kept old folder.
pub(super) fn name_of(dir: &Path) -> String {
    dir.file_name().map_or("out".into(), |n| n.to_string_lossy().into_owned())
}

/// Refuses `dir` unless `folder` (the folder it will be written into) is a folder this process
/// can write into.
pub(super) fn writable(dir: &Path, folder: &Path) -> Result<(), WriteError> {
    if !std::fs::metadata(folder).is_ok_and(|m| m.is_dir()) {
        return Err(refuse(dir, format!("{} is not a folder", shown(folder))));
    }
    if rustix::fs::access(folder, rustix::fs::Access::WRITE_OK).is_err() {
        return Err(refuse(dir, format!("{} is not writable", shown(folder))));
    }
    Ok(())
}

/// The deepest existing ancestor of `path` (itself included).
pub(super) fn existing_ancestor(path: &Path) -> PathBuf {
    let mut head = path.to_path_buf();
    while std::fs::symlink_metadata(&head).is_err() {
        match head.parent() {
            Some(p) if !p.as_os_str().is_empty() => head = p.to_path_buf(),
            _ => return PathBuf::from("."),
        }
    }
    head
}

impl Folder {
    /// What the folder holds, refused unless it may be replaced ([`Folder::check`]).
    pub(super) fn existing(&self, inputs: &[&Path]) -> Result<Existing, WriteError> {
        let dir = &self.dir;
        if dir.as_os_str().is_empty() {
            return Err(WriteError::Input("--out: empty path; give the folder to write".into()));
        }
        if dir.file_name().is_none() {
            return Err(refuse(dir, "`.`, `..` and `/` are never result folders; give a new folder"));
        }
        let Some(real) = resolved(dir) else {
            return Err(refuse(dir, "cannot resolve the path"));
        };
        let cwd = std::env::current_dir().ok().and_then(|d| d.canonicalize().ok());
        if let Some(cwd) = cwd.filter(|c| c.starts_with(&real)) {
            let what = if cwd == real { "is the working directory" } else { "holds the working directory" };
            return Err(refuse(dir, format!("{what}; give a new folder")));
        }
        for input in inputs {
            if resolved(input).is_some_and(|i| i.starts_with(&real)) {
                return Err(refuse(dir, format!("holds the input {}; give a new folder", shown(input))));
            }
        }
        let existing = match std::fs::symlink_metadata(dir) {
            Err(_) => Existing::Absent,
            Ok(meta) if meta.file_type().is_symlink() => {
                return Err(refuse(dir, "is a symbolic link; give a new folder or one an earlier run wrote"))
            }
            Ok(meta) if !meta.is_dir() => return Err(refuse(dir, "is a file; the output must be a folder")),
            Ok(_) => self.contents()?,
        };
        let parent = match existing {
            Existing::Absent => existing_ancestor(dir),
            _ => parent_of(dir),
        };
        writable(dir, &parent)?;
        Ok(existing)
    }

    /// The folder's entries against its marker.
    fn contents(&self) -> Result<Existing, WriteError> {
        let dir = &self.dir;
        let listing = std::fs::read_dir(dir).map_err(|e| refuse(dir, format!("cannot read the folder: {e}")))?;
        let mut names = Vec::new();
        for entry in listing {
            let entry = entry.map_err(|e| refuse(dir, format!("cannot read the folder: {e}")))?;
            names.push(entry.file_name().to_string_lossy().into_owned());
        }
        if names.is_empty() {
            return Ok(Existing::Empty);
        }
        names.sort();
        // Without a marker every entry is foreign; with one, every entry it does not list.
        let listed = read_marker(dir);
        let foreign: Vec<&String> = match &listed {
            None => names.iter().collect(),
            Some(listed) => names.iter().filter(|n| *n != MARKER && !listed.contains(n)).collect(),
        };
        if let Some(first) = foreign.first() {
            let (whose, what_to_do) = match listed {
                None => ("this program", "give a new folder or an empty one"),
                Some(_) => ("an earlier run", "move them or give a new folder"),
            };
            return Err(refuse(
                dir,
                format!(
                    "holds {} {whose} did not write (first: {}); {what_to_do}",
                    entries(foreign.len()),
                    spine_check::shown(first)
                ),
            ));
        }
        for name in names.iter().filter(|n| *n != MARKER) {
            let ok = std::fs::symlink_metadata(dir.join(name)).is_ok_and(|m| m.is_file());
            if !ok {
                return Err(refuse(dir, format!("{} is not a file an earlier run wrote", spine_check::shown(name))));
            }
        }
        Ok(Existing::Ours)
    }
}
