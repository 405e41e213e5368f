//! Reading an input file with a size bound that holds for every kind of file: regular files,
//! devices (`/dev/zero`), pipes and FIFOs, whose size the file system does not know. The read
//! stops one byte past the bound, so no input can make the program read or hold more.

use std::io::Read as _;
use std::path::Path;

/// Why an input file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// The file is a folder.
    #[error("{path}: a folder, not a file")]
    Folder { path: String },
    /// Longer than the bound.
    #[error("{path}: {what}: more than {max} bytes; at most {max} are accepted")]
    TooLong { path: String, what: &'static str, max: usize },
    /// Not UTF-8 text.
    #[error("{path}: {what}: not UTF-8 text (byte {at})")]
    NotText { path: String, what: &'static str, at: usize },
}

/// The text of the file at `path` (a `what`: "case file", "shard"), at most `max` bytes.
///
/// ```
/// let e = spine_case::read_text(std::path::Path::new("/dev/zero"), "case file", 1000).unwrap_err();
/// assert!(e.to_string().contains("at most 1000"));
/// ```
pub fn read_text(path: &Path, what: &'static str, max: usize) -> Result<String, ReadError> {
    let name = spine_check::shown_within(&path.display().to_string(), 200);
    let io = |source| ReadError::Io { path: name.clone(), source };
    if std::fs::metadata(path).map_err(io)?.is_dir() {
        return Err(ReadError::Folder { path: name });
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(max as u64 + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() > max {
        return Err(ReadError::TooLong { path: name, what, max });
    }
    String::from_utf8(bytes).map_err(|e| ReadError::NotText { path: name, what, at: e.utf8_error().valid_up_to() })
}
