//! Reading the files a scene names: the scene file, its includes, meshes, textures and
//! environment maps all go through [`read`], which
//! - refuses what is not a regular file: a link to `/dev/zero` or `/dev/urandom`, a FIFO or a
//!   directory would otherwise be read until memory runs out, or forever;
//! - refuses a file larger than [`max_bytes`] before reading it;
//! - notes the file in the scene's [`inputs`](super::Scene::inputs) (through [`collect`]), so
//!   that a run can refuse to write over anything it read.

use std::cell::RefCell;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The largest file a scene may name: 4 GiB, or half the host's available memory where that
/// is less (a file is held whole while it is parsed).
pub fn max_bytes() -> u64 {
    const CAP: u64 = 4 << 30;
    available_memory().map_or(CAP, |m| CAP.min(m / 2))
}

/// `MemAvailable` of `/proc/meminfo`, in bytes (Linux), else `None`.
pub(crate) fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

thread_local! {
    /// The files read since [`collect`] began on this thread, canonical, each once.
    static READ: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

/// Runs `f`, giving back with its result every file [`read`] read meanwhile on this thread
/// (canonical paths, in the order first read).
pub fn collect<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let outer = READ.with(|r| r.replace(Some(Vec::new())));
    let value = f();
    let read = READ.with(|r| r.replace(outer)).unwrap_or_default();
    (value, read)
}

/// Notes `path` as read, where a [`collect`] is running.
fn note(path: &Path) {
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    READ.with(|r| {
        if let Some(read) = r.borrow_mut().as_mut() {
            if !read.contains(&canonical) {
                read.push(canonical);
            }
        }
    });
}

/// The bytes of `path`, a regular file of at most [`max_bytes`]. Errors are plain messages
/// (the caller names the file and the key that names it).
pub fn read(path: &Path) -> Result<Vec<u8>, String> {
    let mut file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let metadata = file.metadata().map_err(|e| e.to_string())?;
    if !metadata.is_file() {
        let what = if metadata.is_dir() { "a directory" } else { "not a regular file (a device, pipe or socket)" };
        return Err(format!("{what}: a scene reads files only"));
    }
    let limit = max_bytes();
    if metadata.len() > limit {
        return Err(format!("{} bytes, more than the {} bytes a scene file may have here", metadata.len(), limit));
    }
    // Read at most one byte more than the limit: a file that grows while read is caught too.
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.by_ref().take(limit + 1).read_to_end(&mut bytes).map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!("more than the {limit} bytes a scene file may have here"));
    }
    note(path);
    Ok(bytes)
}

/// [`read`] as UTF-8 text; the error names the line of the first byte that is not.
pub fn read_text(path: &Path) -> Result<String, String> {
    let bytes = read(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let line = e.as_bytes()[..e.utf8_error().valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        format!("line {line}: not UTF-8 text")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_and_files_noted() {
        #[cfg(unix)]
        assert!(read(Path::new("/dev/zero")).unwrap_err().contains("not a regular file"));
        let dir = std::env::temp_dir();
        assert!(read(&dir).unwrap_err().contains("a directory"));
        let file = dir.join(format!("sppm-files-{}.txt", std::process::id()));
        std::fs::write(&file, b"abc").unwrap();
        let (bytes, read_files) = collect(|| read(&file).unwrap());
        assert_eq!(bytes, b"abc");
        assert_eq!(read_files, vec![file.canonicalize().unwrap()]);
        // Outside a collect nothing is noted, and nothing leaks into the next.
        read(&file).unwrap();
        let ((), none) = collect(|| ());
        assert!(none.is_empty());
        std::fs::remove_file(&file).unwrap();
    }
}
