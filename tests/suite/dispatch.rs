//! Every BSDF family and every emitter kind is in each dispatcher. A family is its two files,
//! `src/scene/material/<family>.rs` and `shaders/shared/bsdf/<family>.wgsl`, each declaring
//! its `MATERIAL_*` kind with one value; an emitter kind likewise in `src/scene/emitter/` and
//! `shaders/shared/emitter/` with its `EMITTER_*`. The dispatchers (`material/mod.rs` and
//! `bsdf.wgsl`, `emitter/mod.rs` and `lights.wgsl`) must name each one, and the library must
//! read, pack and specialize kernels for each. A file added without its dispatch arms fails
//! here.

use crate::common::scene_text::BASE;
use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::layout::Features;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The `u32` constants named `<prefix>...` declared in `text` (`const NAME: u32 = 3u;` in
/// WGSL, `pub const NAME: u32 = 3;` in Rust).
fn constants(text: &str, prefix: &str) -> Vec<(String, u32)> {
    text.lines()
        .filter_map(|l| {
            let rest = l.trim().trim_start_matches("pub ").strip_prefix("const ")?.strip_prefix(prefix)?;
            let (name, value) = rest.split_once(": u32 = ")?;
            let value = value.trim_end_matches(';').trim_end_matches('u').parse().ok()?;
            Some((format!("{prefix}{name}"), value))
        })
        .collect()
}

/// The kinds of one dispatcher: (file stem, constant, value) of every WGSL file in `dir` that
/// declares a `<prefix>*` constant, each checked against its host file in `host_dir`.
fn kinds(wgsl_dir: &str, host_dir: &str, prefix: &str) -> Vec<(String, String, u32)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(root().join(wgsl_dir)).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let declared = constants(&read(&path), prefix);
        match declared.as_slice() {
            [] => continue,
            [(name, value)] => {
                let host = root().join(host_dir).join(format!("{stem}.rs"));
                assert!(host.exists(), "{name} ({}) has no host file {}", path.display(), host.display());
                assert_eq!(
                    constants(&read(&host), prefix),
                    [(name.clone(), *value)],
                    "{} declares {name} = {value}: its host file {} must declare the same",
                    path.display(),
                    host.display()
                );
                out.push((stem, name.clone(), *value));
            }
            more => panic!("{} declares {more:?}: one kind a file", path.display()),
        }
    }
    out.sort_by_key(|k| k.2);
    let values: BTreeSet<u32> = out.iter().map(|k| k.2).collect();
    assert_eq!(values.len(), out.len(), "two kinds share a value: {out:?}");
    out
}

/// The text of Rust or WGSL function `name` in `text`: from `fn name(` to its closing brace.
fn function<'a>(text: &'a str, name: &str) -> &'a str {
    let start = text.find(&format!("fn {name}(")).unwrap_or_else(|| panic!("no fn {name}"));
    let open = start + text[start..].find('{').unwrap();
    let mut depth = 0;
    for (i, c) in text[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return &text[start..open + i + 1];
                }
            }
            _ => {}
        }
    }
    panic!("fn {name} does not close")
}

/// The `const NAME: ... = ...;` item `name` of `text` (a table).
fn table<'a>(text: &'a str, name: &str) -> &'a str {
    let start = text.find(&format!("const {name}: ")).unwrap_or_else(|| panic!("no const {name}"));
    &text[start..start + text[start..].find("];").unwrap()]
}

#[test]
fn every_bsdf_family_is_in_each_dispatcher() {
    let families = kinds("shaders/shared/bsdf", "src/scene/material", "MATERIAL_");
    let names: Vec<&str> = families.iter().map(|f| f.0.as_str()).collect();
    assert_eq!(names, ["diffuse", "conductor", "dielectric", "plastic", "thin_dielectric"], "the families, by kind");
    let host = read(&root().join("src/scene/material/mod.rs"));
    let wgsl = read(&root().join("shaders/shared/bsdf.wgsl"));
    for (family, kind, _) in &families {
        let own = read(&root().join(format!("shaders/shared/bsdf/{family}.wgsl")));
        assert!(host.contains(&format!("\nmod {family};")), "material/mod.rs lacks `mod {family};`");
        assert!(host.contains(&format!("pub use {family}::{kind};")), "material/mod.rs does not export {kind}");
        for dispatcher in ["describe", "toml_keys", "check", "gpu", "turn_on_features"] {
            assert!(function(&host, dispatcher).contains(&format!("{family}::")), "material/mod.rs: {dispatcher} lacks {family}");
        }
        for list in ["TOML_TYPES", "MITSUBA_PLUGINS"] {
            assert!(table(&host, list).contains(&format!("{family}::")), "material/mod.rs: {list} lacks {family}");
        }
        assert!(wgsl.contains(&format!("#import bsdf/{family}\n")), "bsdf.wgsl does not import bsdf/{family}");
        assert!(own.contains(&format!("fn {family}_sample(")), "bsdf/{family}.wgsl has no {family}_sample");
        assert!(function(&wgsl, "bsdf_sample").contains(&format!("{family}_sample(")), "bsdf_sample lacks {family}");
        // A family whose lobes are not all deltas is evaluated for next-event estimation.
        if own.contains(&format!("fn {family}_eval(")) {
            assert!(function(&wgsl, "bsdf_eval").contains(&format!("{family}_eval(")), "bsdf_eval lacks {family}");
        }
    }

    // Through the library: a material of each TOML type reads, checks and packs to a family's
    // kind, every family is reached, and every type but the diffuse turns on a kernel feature
    // of its own.
    let params = |t: &str| match t {
        "diffuse" => "albedo = 0.5",
        "mirror" => "albedo = 0.9",
        "glossy" => "albedo = 0.9, roughness = 0.2",
        "dielectric" | "thin_dielectric" => "ior = 1.5",
        "plastic" => "albedo = 0.5, ior = 1.5",
        "null" => "",
        other => panic!("the TOML material type `{other}` needs its parameters here"),
    };
    let on = |f: Features| -> BTreeSet<&'static str> { f.constants().into_iter().filter(|c| c.1 == 1.0).map(|c| c.0).collect() };
    let mut reached = BTreeSet::new();
    let mut features = Vec::new();
    for t in sppm_gpu::scene::material::toml_types() {
        let text = format!(
            "{BASE}m = {{ type = \"{t}\" {} }}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\
             material = \"m\"\n[[lights]]\ntype = \"point\"\nposition = [0, 0, 3]\nintensity = 1\n",
            if params(t).is_empty() { String::new() } else { format!(", {}", params(t)) }
        );
        let scene = sppm_gpu::scene::load_str(&text, Path::new("t.toml")).unwrap_or_else(|e| panic!("{t}: {e}"));
        let data = SceneData::new(&scene).unwrap();
        let kind = data.materials[1].kind;
        assert!(families.iter().any(|f| f.2 == kind), "{t} packs to kind {kind}, no family's");
        reached.insert(kind);
        features.push((t, on(Features::of(&data))));
    }
    assert_eq!(reached.len(), families.len(), "every family is some TOML type's");
    let diffuse = &features.iter().find(|f| f.0 == "diffuse").unwrap().1;
    for (t, own) in &features {
        assert!(*t == "diffuse" || !own.is_subset(diffuse), "{t} turns on no feature of its own: {own:?}");
    }
}
