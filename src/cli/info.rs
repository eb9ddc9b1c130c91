//! `sppm-gpu info SCENE`: what a scene holds, as loaded (TOML or Mitsuba XML): the image and
//! its settings, the camera, shapes, triangles, materials and lights by kind, and the kernel
//! features it turns on (the `USES_*` constants its kernels are specialized with).

use sppm_gpu::gpu::scene_buffers::SceneData;
use sppm_gpu::layout::Features;
use sppm_gpu::scene::{Method, Named, Phase, PixelFilter, Scene, ShapeKind};
use std::collections::BTreeMap;
use std::fmt::Write;

/// The report for `scene`, as printed.
pub fn report(scene: &Scene) -> Result<String, sppm_gpu::scene::SceneError> {
    let mut out = String::new();
    let r = &scene.render;
    let format = if sppm_gpu::scene::is_mitsuba_xml(&scene.path) {
        "Mitsuba scene XML"
    } else if sppm_gpu::scene::is_pbrt(&scene.path) {
        "pbrt-v4"
    } else {
        "TOML"
    };
    let _ = writeln!(out, "scene:      {} ({format})", scene.path.display());
    let filter = match r.filter {
        PixelFilter::Box => "box".to_string(),
        PixelFilter::Tent { radius } => format!("tent, radius {radius} px"),
        PixelFilter::Gaussian { stddev } => format!("gaussian, stddev {stddev} px"),
    };
    let _ = writeln!(out, "image:      {} x {}, {filter} filter", r.width, r.height);
    let method = r.method.name();
    let radius = r.radius.map_or_else(|| "automatic".to_string(), |x| x.to_string());
    let limit = r.time_limit.map_or_else(String::new, |t| format!(", at most {t} s"));
    // Only the settings the method reads.
    let _ = match r.method {
        Method::Sppm => writeln!(
            out,
            "render:     {method}, {} passes{limit}, {} photons and {} camera samples a pixel a pass, radius {radius}, \
             alpha {}, max depth {}, seed {}",
            r.iterations, r.photons, r.spp, r.alpha, r.max_depth, r.seed
        ),
        Method::Pt | Method::PtNee => writeln!(
            out,
            "render:     {method}, {} samples a pixel{limit}, max depth {}, seed {}",
            r.iterations, r.max_depth, r.seed
        ),
        Method::Lt | Method::Bpt | Method::Vcm => writeln!(
            out,
            "render:     {method}, {} passes of a light subpath a pixel{limit}, max depth {}, seed {}",
            r.iterations, r.max_depth, r.seed
        ),
    };
    let c = &scene.camera;
    let mut lens = if c.aperture_radius > 0.0 {
        format!(", aperture radius {} focused at {}", c.aperture_radius, c.focus_distance)
    } else {
        String::new()
    };
    if let Some(w) = c.crop {
        lens += &format!(", the film's window {} to {}", w.min, w.max);
    }
    // Every number as the shortest decimal of its f32 (`40`, not `40.0000`).
    let _ =
        writeln!(out, "camera:     at {} looking at {}, up {}, vertical fov {} deg{lens}", c.position, c.look_at, c.up, c.fov);
    let mut shapes = BTreeMap::new();
    for s in &scene.shapes {
        let kind = match s.kind {
            ShapeKind::Quad => "quad",
            ShapeKind::Sphere => "sphere",
            ShapeKind::Cube => "cube",
            ShapeKind::Mesh => "mesh",
        };
        *shapes.entry(kind).or_insert(0) += 1;
    }
    let _ = writeln!(
        out,
        "shapes:     {} ({}); {} triangles, {} analytic spheres",
        scene.shapes.len(),
        counts(&shapes),
        scene.triangles.len(),
        scene.spheres.len()
    );
    let mut materials = BTreeMap::new();
    for m in &scene.materials {
        let kind = m.kind.describe();
        *materials.entry(kind).or_insert(0) += 1;
    }
    let one_sided = scene.materials.iter().filter(|m| m.one_sided).count();
    let _ = writeln!(
        out,
        "materials:  {} ({}); {one_sided} one-sided, {} textures",
        scene.materials.len(),
        counts(&materials),
        scene.textures.len()
    );
    let mut lights = BTreeMap::new();
    for kind in sppm_gpu::scene::emitter::names(scene) {
        *lights.entry(kind).or_insert(0) += 1;
    }
    let _ = writeln!(out, "lights:     {} ({})", lights.values().sum::<usize>(), counts(&lights));
    if !scene.media.is_empty() {
        let name = |i: Option<u32>| i.map_or("vacuum", |i| scene.media[i as usize].name.as_str());
        let each: Vec<String> = scene
            .media
            .iter()
            .map(|m| {
                let phase = match m.phase {
                    Phase::Isotropic => "isotropic".to_owned(),
                    Phase::HenyeyGreenstein { g } => format!("hg g {g}"),
                };
                format!("{}: sigma_a {}, sigma_s {}, {phase}", m.name, m.sigma_a, m.sigma_s)
            })
            .collect();
        let bounds = scene.shapes.iter().filter(|s| s.interior.is_some() || s.exterior.is_some()).count();
        let _ = writeln!(
            out,
            "media:      {} ({}); camera in {}, {bounds} shapes bound media",
            scene.media.len(),
            each.join("; "),
            name(scene.camera.medium)
        );
    }
    let data = SceneData::new(scene)?;
    let on: Vec<&str> = Features::of(&data).constants().into_iter().filter(|(_, v)| *v != 0.0).map(|(name, _)| name).collect();
    let _ = writeln!(out, "kernels:    {}", on.join(" "));
    Ok(out)
}

/// `3 diffuse, 1 mirror`.
fn counts(by_kind: &BTreeMap<&str, usize>) -> String {
    if by_kind.is_empty() {
        return "none".into();
    }
    by_kind.iter().map(|(k, n)| format!("{n} {k}")).collect::<Vec<_>>().join(", ")
}
