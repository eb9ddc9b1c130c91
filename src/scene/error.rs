//! Scene loading errors: each names the file, the line and the key.
use std::fmt;
use std::path::{Path, PathBuf};

/// An error in a scene or one of the files it names.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The file the error is in: the scene, or the mesh or texture it names.
    pub file: PathBuf,
    /// 1-based line, when the error has a place in the file.
    pub line: Option<usize>,
    /// Dotted key path, e.g. `render.width` or `shapes[3].material`.
    pub key: Option<String>,
    /// What is wrong, without the place (which `Display` prepends).
    pub message: String,
}

impl SceneError {
    /// An error in `file`, at `line` when it has a place, about `key` when it names one.
    pub fn new(file: &Path, line: Option<usize>, key: Option<&str>, message: impl Into<String>) -> Self {
        SceneError { file: file.to_path_buf(), line, key: key.map(str::to_owned), message: message.into() }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": key `{key}`")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for SceneError {}
