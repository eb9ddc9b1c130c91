//! Embeds every WGSL file under `shaders/` in the library: writes `shader_files.rs` to
//! `OUT_DIR`, a table of (name, source) that `src/gpu/kernel.rs` includes. A kernel's name is
//! its file's stem (`shaders/<kernel>.wgsl`); a shared file's is its path under
//! `shaders/shared/` without the extension (`bsdf/diffuse`), as `#import` lines name it.
//! Adding a shader file is then all it takes for `#import` to find it.

use std::path::{Path, PathBuf};

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.unwrap().path();
        if path.is_dir() {
            wgsl_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "wgsl") {
            out.push(path);
        }
    }
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    println!("cargo:rerun-if-changed={}", root.display());
    let mut files = Vec::new();
    wgsl_files(&root, &mut files);
    files.sort();
    let mut table = String::from("&[\n");
    let mut names: Vec<String> = Vec::new();
    for path in &files {
        let relative = path.strip_prefix(&root).unwrap().with_extension("");
        let relative = relative.strip_prefix("shared").unwrap_or(&relative);
        let name = relative.components().map(|c| c.as_os_str().to_str().unwrap()).collect::<Vec<_>>().join("/");
        assert!(!names.contains(&name), "two shader files are named `{name}`: a kernel and a shared file");
        table.push_str(&format!("    ({name:?}, include_str!({:?})),\n", path.display().to_string()));
        names.push(name);
    }
    table.push_str("]\n");
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("shader_files.rs");
    std::fs::write(out, table).unwrap();
}
