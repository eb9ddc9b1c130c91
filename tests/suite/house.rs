//! The house's layers, read from the source: which module may use which, and no two files of
//! a module that use each other. A change that points an arrow up the house fails here.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The library's modules from the bottom up: each may use those before it, none after.
/// `error` is left out: it gathers every layer's error type into one.
const LAYERS: &[&str] = &[
    "layout",
    "sampler",
    "image_io",
    "metrics",
    "scene",
    "accel",
    "gpu",
    "integrators",
    "pacing",
    "checkpoint",
    "batch",
    "experiments",
    "view",
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The code of `path` without its comments (a line's `//` onwards).
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// Every `.rs` file of module `name` (`src/name.rs` or `src/name/**`).
fn files_of(name: &str) -> Vec<PathBuf> {
    let single = src().join(format!("{name}.rs"));
    if single.exists() {
        return vec![single];
    }
    let mut out = Vec::new();
    let mut stack = vec![src().join(name)];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out
}

/// The names `prefix` is followed by in `code` (`crate::` gives the top-level modules used).
fn names_after<'a>(code: &'a str, prefix: &str) -> BTreeSet<&'a str> {
    code.match_indices(prefix)
        .map(|(i, _)| {
            let rest = &code[i + prefix.len()..];
            let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
            &rest[..end]
        })
        .filter(|n| !n.is_empty())
        .collect()
}

#[test]
fn no_module_uses_one_above_it() {
    let mut wrong = Vec::new();
    for (level, module) in LAYERS.iter().enumerate() {
        for file in files_of(module) {
            for used in names_after(&code(&file), "crate::") {
                if let Some(above) = LAYERS.iter().position(|m| *m == used).filter(|&l| l > level) {
                    wrong.push(format!("{} uses crate::{}", file.display(), LAYERS[above]));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "arrows up the house:\n{}", wrong.join("\n"));
}

#[test]
fn scene_and_layout_know_no_gpu_api() {
    for module in ["scene", "layout"] {
        for file in files_of(module) {
            let text = std::fs::read_to_string(&file).unwrap();
            assert!(!text.contains("wgpu"), "{} names wgpu", file.display());
        }
    }
}

/// Within each module that is a folder, the files (its `mod.rs`, the module's index, aside)
/// that use one another through `super::` or `crate::module::` form no circle.
#[test]
fn no_circles_between_a_modules_files() {
    for module in LAYERS {
        let dir = src().join(module);
        if !dir.is_dir() {
            continue;
        }
        let files: BTreeMap<String, String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "rs") && !p.ends_with("mod.rs"))
            .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), code(&p)))
            .collect();
        let uses = |from: &str| -> BTreeSet<String> {
            let text = &files[from];
            let mut names = names_after(text, "super::");
            names.extend(names_after(text, &format!("crate::{module}::")));
            names.into_iter().filter(|n| *n != from && files.contains_key(*n)).map(str::to_owned).collect()
        };
        for a in files.keys() {
            // Depth-first from `a`: reaching `a` again is a circle.
            let mut seen = BTreeSet::new();
            let mut stack: Vec<(String, Vec<String>)> = vec![(a.clone(), vec![a.clone()])];
            while let Some((at, path)) = stack.pop() {
                for next in uses(&at) {
                    assert!(&next != a, "a circle in src/{module}/: {} -> {next}", path.join(" -> "));
                    if seen.insert(next.clone()) {
                        let mut longer = path.clone();
                        longer.push(next.clone());
                        stack.push((next, longer));
                    }
                }
            }
        }
    }
}
