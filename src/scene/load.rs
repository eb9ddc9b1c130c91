//! Placeholder: replaced by the loader.
use super::{Scene, SceneError};
use std::path::Path;

pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        file: path.to_path_buf(),
        line: None,
        key: None,
        message: e.to_string(),
    })?;
    load_str(&text, path)
}

pub fn load_str(_text: &str, path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError { file: path.to_path_buf(), line: None, key: None, message: "loader not written yet".into() })
}
