//! One rule for every path the program writes (`-o`, `--partial`, `--checkpoint`, `diff
//! --error-image`, `merge -o`, `convert -o`, the files of an experiment's `--out` folder),
//! checked before any work is done:
//! 1. never a file the run reads: the scene and every file it names (includes, meshes,
//!    textures, environment maps), an image compared, a part merged, a checkpoint resumed
//!    (`--resume F --checkpoint F` goes on writing `F`, which is its purpose);
//! 2. an existing file is replaced only by one of its own kind, with a note: a PNG by a PNG,
//!    an EXR by an EXR, a checkpoint by a checkpoint, an experiment's CSV by the same CSV;
//!    anything else there is refused (a scene, a text, another program's file: remove it
//!    first);
//! 3. the path names a file (not a folder, no trailing `/`) in a directory that exists and
//!    takes new files.

use sppm_gpu::Error;
use std::io::Read;
use std::path::{Path, PathBuf};

/// What is written at a path, and so what an existing file there must be to be replaced.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    /// An image, PNG or EXR by the extension (which must be one of them).
    Image,
    /// A partial image of a batch: an EXR.
    Partial,
    /// A checkpoint (`sppm_gpu::checkpoint`).
    Checkpoint,
    /// A CSV whose first line is this header.
    Csv(&'static str),
    /// A file written only where none is (`convert`'s TOML).
    New,
}

/// The leading bytes that mark a file of each format.
const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";
const EXR_MAGIC: &[u8] = &[0x76, 0x2f, 0x31, 0x01];

/// The files a run reads, canonical, for [`check`].
#[derive(Default, Debug)]
pub(crate) struct Inputs(Vec<PathBuf>);

impl Inputs {
    /// The files among `paths` that exist (an input that does not exist fails when read).
    pub(crate) fn of<'a>(paths: impl IntoIterator<Item = &'a Path>) -> Self {
        let mut inputs = Inputs::default();
        inputs.extend(paths.into_iter().map(Path::to_path_buf));
        inputs
    }

    /// Adds `paths` (canonicalized where they exist).
    pub(crate) fn extend(&mut self, paths: impl IntoIterator<Item = PathBuf>) {
        for path in paths {
            if let Ok(canonical) = path.canonicalize() {
                if !self.0.contains(&canonical) {
                    self.0.push(canonical);
                }
            }
        }
    }

    fn contains(&self, path: &Path) -> bool {
        path.canonicalize().is_ok_and(|p| self.0.contains(&p))
    }
}

/// Whether `output` may be written as `kind` by a run that reads `inputs` (the module's
/// rule); `Ok(true)` when it replaces a file already there.
pub(crate) fn check(output: &Path, kind: Kind, inputs: &Inputs) -> Result<bool, Error> {
    let refuse = |why: String| Err(Error::Setting(format!("{}: {why}", output.display())));
    let ext = output.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match (kind, ext.as_deref()) {
        (Kind::Image, Some("png" | "exr")) | (Kind::Partial, Some("exr")) => {}
        (Kind::Image, _) => return refuse("the output must end in .png or .exr".into()),
        (Kind::Partial, _) => return refuse("a partial image is an .exr file".into()),
        _ => {}
    }
    let text = output.as_os_str().to_string_lossy();
    if text.ends_with(std::path::MAIN_SEPARATOR) || text.ends_with('/') || output.is_dir() {
        return refuse("names a directory: give a file name".into());
    }
    let dir = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return refuse(format!("the directory {} does not exist", dir.display()));
    }
    if inputs.contains(output) {
        return refuse("the run reads this file: it will not write over its own input".into());
    }
    let cannot = |e: std::io::Error| Error::Setting(format!("{}: cannot be written: {e}", output.display()));
    let exists = output.symlink_metadata().is_ok();
    if exists {
        if !output.is_file() {
            return refuse("exists and is not a regular file".into());
        }
        if let Kind::New = kind {
            return refuse("exists already: this command writes new files only".into());
        }
        if let Some(what) = not_of_kind(output, kind).map_err(cannot)? {
            return refuse(format!(
                "exists and is {what}: sppm-gpu replaces only a file of the kind it writes there; remove it first"
            ));
        }
        // Opened for writing without truncating: the file is left as it is.
        std::fs::OpenOptions::new().write(true).open(output).map_err(cannot)?;
    } else {
        // A file made and removed beside it: the directory takes new files.
        let name = output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let probe = dir.join(format!(".{name}.{}.sppm-gpu-probe", std::process::id()));
        std::fs::File::create_new(&probe).map_err(cannot)?;
        let _ = std::fs::remove_file(&probe);
    }
    Ok(exists)
}

/// `None` when the existing file `path` is of `kind`, else what it is, for the message.
fn not_of_kind(path: &Path, kind: Kind) -> std::io::Result<Option<String>> {
    let mut head = Vec::new();
    std::fs::File::open(path)?.take(256).read_to_end(&mut head)?;
    let is_exr = || head.starts_with(EXR_MAGIC);
    let of_kind = match kind {
        Kind::Image | Kind::Partial if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) => {
            head.starts_with(PNG_MAGIC)
        }
        Kind::Image | Kind::Partial => is_exr(),
        Kind::Checkpoint => head.starts_with(sppm_gpu::checkpoint::MAGIC),
        Kind::Csv(header) => head.starts_with(header.as_bytes()),
        Kind::New => false,
    };
    if of_kind {
        return Ok(None);
    }
    let what = if head.starts_with(PNG_MAGIC) {
        "a PNG image"
    } else if is_exr() {
        "an EXR image"
    } else if head.starts_with(sppm_gpu::checkpoint::MAGIC) {
        "a checkpoint"
    } else if head.is_empty() {
        "an empty file"
    } else {
        "another kind of file"
    };
    let wanted = match kind {
        Kind::Image | Kind::Partial => "the image",
        Kind::Checkpoint => "the checkpoint",
        Kind::Csv(_) => "the table",
        Kind::New => "a new file",
    };
    Ok(Some(format!("{what}, not of the kind of {wanted} written here")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir() -> PathBuf {
        let dir = std::env::temp_dir().join(format!("sppm-output-rule-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn an_existing_file_is_replaced_only_by_its_own_kind() {
        let dir = dir();
        let png = dir.join("a.png");
        std::fs::write(&png, PNG_MAGIC).unwrap();
        let scene = dir.join("scene.png");
        std::fs::write(&scene, b"[render]\n").unwrap();
        let none = Inputs::default();
        assert!(check(&png, Kind::Image, &none).unwrap());
        assert!(check(&dir.join("new.exr"), Kind::Image, &none).is_ok_and(|replaces| !replaces));
        let e = check(&scene, Kind::Image, &none).unwrap_err().to_string();
        assert!(e.contains("another kind of file") && e.contains("remove it first"), "{e}");
        let e = check(&png, Kind::Checkpoint, &none).unwrap_err().to_string();
        assert!(e.contains("a PNG image, not of the kind of the checkpoint"), "{e}");
        let e = check(&png, Kind::Image, &Inputs::of([png.as_path()])).unwrap_err().to_string();
        assert!(e.contains("its own input"), "{e}");
        let e = check(&dir.join("x.png/"), Kind::Image, &none).unwrap_err().to_string();
        assert!(e.contains("names a directory"), "{e}");
        let e = check(&dir.join("nodir/ck.bin"), Kind::Checkpoint, &none).unwrap_err().to_string();
        assert!(e.contains("does not exist"), "{e}");
        let csv = dir.join("compare.csv");
        std::fs::write(&csv, "method,seconds\nsppm,1\n").unwrap();
        assert!(check(&csv, Kind::Csv("method,"), &none).unwrap());
        assert!(check(&csv, Kind::Csv("pass,"), &none).is_err());
        assert!(check(&csv, Kind::New, &none).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
