//! Every BSDF family and every emitter kind is in each dispatcher. A family is its two files,
//! `src/scene/material/<family>.rs` and `shaders/shared/bsdf/<family>.wgsl`, each declaring
//! its `MATERIAL_*` kind with one value; an emitter kind likewise in `src/scene/emitter/` and
//! `shaders/shared/emitter/` with its `EMITTER_*`. The dispatchers (`material/mod.rs` and
//! `bsdf.wgsl`, `emitter/mod.rs` and `lights.wgsl`) must name each one, and the library must
//! read, pack and specialize kernels for each. A file added without its dispatch arms fails
//! here.

use crate::common::scene_text::{with_light, BASE, QUAD};
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

/// The names of the constants of type `ty` that host file `text` declares (`pub(super) const
/// TOML: TomlType`).
fn consts_of_type<'a>(text: &'a str, ty: &str) -> Vec<&'a str> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("pub(super) const ")?.split_once(&format!(": {ty} ")).map(|(name, _)| name))
        .collect()
}

/// Every TOML type and Mitsuba plugin that the host file of `kind` declares is in its
/// dispatcher's table.
fn tables_list(host: &str, own: &str, kind: &str, tables: [(&str, &str); 2]) {
    for (ty, list) in tables {
        for name in consts_of_type(own, ty) {
            assert!(table(host, list).contains(&format!("{kind}::{name}")), "{list} lacks {kind}::{name}");
        }
    }
}

#[test]
fn every_bsdf_family_is_in_each_dispatcher() {
    let families = kinds("shaders/shared/bsdf", "src/scene/material", "MATERIAL_");
    assert!(families.len() >= 5, "the families: {families:?}");
    let host = read(&root().join("src/scene/material/mod.rs"));
    let wgsl = read(&root().join("shaders/shared/bsdf.wgsl"));
    for (family, kind, _) in &families {
        let own = read(&root().join(format!("shaders/shared/bsdf/{family}.wgsl")));
        assert!(host.contains(&format!("\nmod {family};")), "material/mod.rs lacks `mod {family};`");
        assert!(host.contains(&format!("pub use {family}::{kind};")), "material/mod.rs does not export {kind}");
        for dispatcher in ["describe", "toml_keys", "check", "gpu", "turn_on_features"] {
            assert!(function(&host, dispatcher).contains(&format!("{family}::")), "material/mod.rs: {dispatcher} lacks {family}");
        }
        let own_host = read(&root().join(format!("src/scene/material/{family}.rs")));
        assert!(!consts_of_type(&own_host, "TomlType").is_empty(), "{family} has no TOML type");
        tables_list(&host, &own_host, family, [("TomlType", "TOML_TYPES"), ("MitsubaPlugins", "MITSUBA_PLUGINS")]);
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
    let mut reached = BTreeSet::new();
    for t in sppm_gpu::scene::material::toml_types() {
        let text = format!(
            "{BASE}m = {{ type = \"{t}\" {} }}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\
             material = \"m\"\n[[lights]]\ntype = \"point\"\nposition = [0, 0, 3]\nintensity = 1\n",
            if params(t).is_empty() { String::new() } else { format!(", {}", params(t)) }
        );
        let scene = sppm_gpu::scene::load_str(&text, Path::new("t.toml")).unwrap_or_else(|e| panic!("{t}: {e}"));
        let mut data = SceneData::new(&scene).unwrap();
        let kind = data.materials[1].kind;
        assert!(families.iter().any(|f| f.2 == kind), "{t} packs to kind {kind}, no family's");
        reached.insert(kind);
        // Its features against those of the same scene with the diffuse material in its place.
        let own = on(&data);
        data.materials[1] = data.materials[0];
        assert!(t == "diffuse" || !own.is_subset(&on(&data)), "{t} turns on no feature of its own: {own:?}");
    }
    assert_eq!(reached.len(), families.len(), "every family is some TOML type's");
}

/// The kernel features a scene's data turns on.
fn on(data: &SceneData) -> BTreeSet<&'static str> {
    Features::of(data).constants().into_iter().filter(|c| c.1 == 1.0).map(|c| c.0).collect()
}

#[test]
fn every_emitter_kind_is_in_each_dispatcher() {
    let kinds = kinds("shaders/shared/emitter", "src/scene/emitter", "EMITTER_");
    assert!(kinds.len() >= 5, "the kinds: {kinds:?}");
    let host = read(&root().join("src/scene/emitter/mod.rs"));
    let wgsl = read(&root().join("shaders/shared/lights.wgsl"));
    for (kind, constant, _) in &kinds {
        let own_host = read(&root().join(format!("src/scene/emitter/{kind}.rs")));
        let own = read(&root().join(format!("shaders/shared/emitter/{kind}.wgsl")));
        assert!(host.contains(&format!("\nmod {kind};")), "emitter/mod.rs lacks `mod {kind};`");
        assert!(
            host.contains(&format!("pub use {kind}::")) && host.contains(constant),
            "emitter/mod.rs does not export {constant}"
        );
        for dispatcher in ["pack", "turn_on_features"] {
            assert!(function(&host, dispatcher).contains(&format!("{kind}::")), "emitter/mod.rs: {dispatcher} lacks {kind}");
        }
        tables_list(&host, &own_host, kind, [("TomlType", "TOML_TYPES"), ("MitsubaPlugin", "MITSUBA_PLUGINS")]);
        assert!(wgsl.contains(&format!("#import emitter/{kind}\n")), "lights.wgsl does not import emitter/{kind}");
        for (entry, dispatcher) in [("sample", "sample_light"), ("emit", "emit_light")] {
            assert!(own.contains(&format!("fn {kind}_{entry}(")), "emitter/{kind}.wgsl has no {kind}_{entry}");
            assert!(function(&wgsl, dispatcher).contains(&format!("{kind}_{entry}(")), "{dispatcher} lacks {kind}");
        }
    }

    // Through the library: a light of each TOML type (and an emitting shape, the area light)
    // reads, checks and packs to a kind's emitter, every kind is reached, and each turns on a
    // kernel feature of its own.
    let params = |t: &str| match t {
        "point" => "position = [0, 0, 3]\nintensity = 1\n".to_owned(),
        "directional" => "direction = [0, 0, -1]\nirradiance = 1\n".into(),
        "spot" => "position = [0, 0, 3]\ndirection = [0, 0, -1]\nintensity = 1\n".into(),
        "constant" => "radiance = 1\n".into(),
        "envmap" => format!("file = \"{}\"\n", root().join("scenes/mitsuba/textures/sky.exr").display()),
        other => panic!("the TOML light type `{other}` needs its parameters here"),
    };
    let shape = format!("[[shapes]]\n{QUAD}");
    let mut reached = BTreeSet::new();
    for t in sppm_gpu::scene::emitter::toml_types().into_iter().map(Some).chain([None]) {
        let text = match t {
            Some(t) => format!("{}{shape}", with_light(&format!("type = \"{t}\"\n{}", params(t)))),
            None => format!("{BASE}{shape}emission = [1, 1, 1]\n"),
        };
        let scene = sppm_gpu::scene::load_str(&text, Path::new("t.toml")).unwrap_or_else(|e| panic!("{t:?}: {e}"));
        let mut data = SceneData::new(&scene).unwrap();
        let kind = data.emitters[0].kind;
        assert!(kinds.iter().any(|k| k.2 == kind), "{t:?} packs to kind {kind}, no kind's");
        reached.insert(kind);
        // Its features against those of the same scene without emitters.
        let own = on(&data);
        data.emitters.clear();
        assert!(!own.is_subset(&on(&data)), "{t:?} turns on no feature of its own: {own:?}");
    }
    assert_eq!(reached.len(), kinds.len(), "every kind is some TOML type's or an emitting shape's");
}
