//! What the preview window's save key writes: the image as EXR and PNG, and the scene as it
//! was rendered (camera, method, passes, settings) as TOML, next to the scene file and under
//! a name no file has yet.

use sppm_gpu::image_io::{self, Rgb32Image};
use sppm_gpu::scene::{Camera, DirectLight, Named, RenderSettings};
use sppm_gpu::Error;
use std::path::{Path, PathBuf};

/// The files of one save.
pub struct Saved {
    pub exr: PathBuf,
    pub png: PathBuf,
    pub toml: PathBuf,
}

/// `DIR/STEM-view-N.{exr,png,toml}` beside `scene` for the smallest N >= 1 for which none of
/// the three exists.
pub fn free_names(scene: &Path) -> Saved {
    let dir = scene.parent().unwrap_or(Path::new(""));
    let stem = scene.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    (1u64..)
        .map(|n| {
            let name = |ext: &str| dir.join(format!("{stem}-view-{n}.{ext}"));
            Saved { exr: name("exr"), png: name("png"), toml: name("toml") }
        })
        .find(|s| !s.exr.exists() && !s.png.exists() && !s.toml.exists())
        .expect("some number is free")
}

/// The scene file's text with the camera, the render settings and `iterations` = `passes`
/// written in, and any time limit taken out: `sppm-gpu` renders it to `image` bit for bit.
/// The rest of the file (shapes, materials, relative paths) is kept; comments are not.
pub fn scene_text(original: &str, camera: &Camera, render: &RenderSettings, passes: u32) -> Result<String, Error> {
    let mut doc: toml::Table = original.parse().map_err(|e| Error::Setting(format!("the scene no longer parses: {e}")))?;
    let v3 = |v: glam::Vec3| toml::Value::Array(v.to_array().iter().map(|&x| float(x)).collect());
    let table = |doc: &mut toml::Table, key: &str| -> Result<toml::Table, Error> {
        match doc.remove(key) {
            None => Ok(toml::Table::new()),
            Some(toml::Value::Table(t)) => Ok(t),
            Some(_) => Err(Error::Setting(format!("the scene's `{key}` is not a table"))),
        }
    };
    let mut cam = table(&mut doc, "camera")?;
    cam.insert("position".into(), v3(camera.position));
    cam.insert("look_at".into(), v3(camera.look_at));
    cam.insert("up".into(), v3(camera.up));
    cam.insert("fov".into(), float(camera.fov));
    cam.insert("aperture_radius".into(), float(camera.aperture_radius));
    cam.insert("focus_distance".into(), float(camera.focus_distance));
    doc.insert("camera".into(), toml::Value::Table(cam));

    let mut r = table(&mut doc, "render")?;
    let int = |v: u32| toml::Value::Integer(v as i64);
    let method = render.method.name();
    r.insert("method".into(), toml::Value::String(method.into()));
    r.insert("iterations".into(), int(passes.max(1)));
    r.insert("width".into(), int(render.width));
    r.insert("height".into(), int(render.height));
    r.insert("photons".into(), int(render.photons));
    r.insert("spp".into(), int(render.spp));
    r.insert("max_depth".into(), int(render.max_depth));
    r.insert("seed".into(), int(render.seed));
    r.insert("alpha".into(), float(render.alpha));
    if let Some(radius) = render.radius {
        r.insert("radius".into(), float(radius));
    }
    let direct = if render.direct == DirectLight::Photons { "photons" } else { "sampled" };
    r.insert("direct".into(), toml::Value::String(direct.into()));
    if let Some(n) = render.direct_samples {
        r.insert("direct_samples".into(), int(n));
    }
    r.remove("time_limit");
    doc.insert("render".into(), toml::Value::Table(r));
    toml::to_string(&doc).map_err(|e| Error::Setting(format!("cannot write the scene: {e}")))
}

/// `x` as TOML: its shortest decimal (`0.6667`, not `0.666700005531311`) where that reads
/// back as the same `f32` through `f64`, as the loader reads it, else its exact value.
fn float(x: f32) -> toml::Value {
    let short: f64 = x.to_string().parse().expect("a float's own text");
    toml::Value::Float(if short as f32 == x { short } else { x as f64 })
}

/// Write `image` and the scene that renders it beside `scene_path`, under new names.
/// The image as EXR and PNG and, when given, the scene `text` as TOML (a Mitsuba XML scene has
/// none: its camera cannot be written back into the XML yet).
pub fn save(scene_path: &Path, image: &Rgb32Image, text: Option<&str>) -> Result<Saved, Error> {
    let saved = free_names(scene_path);
    let write_new = |path: &Path, bytes: &[u8]| -> Result<(), Error> {
        use std::io::Write;
        // create_new: a file that appeared since the names were chosen is not replaced.
        let mut file = std::fs::File::create_new(path).map_err(|e| Error::Setting(format!("{}: {e}", path.display())))?;
        file.write_all(bytes).map_err(|e| Error::Setting(format!("{}: {e}", path.display())))
    };
    if let Some(text) = text {
        write_new(&saved.toml, text.as_bytes())?;
    }
    for path in [&saved.exr, &saved.png] {
        // Claimed first, then written in place by the image writer.
        write_new(path, &[])?;
        image_io::write_image(path, image)?;
    }
    Ok(saved)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sppm_gpu::scene::Method;

    #[test]
    fn names_are_never_taken() {
        let dir = std::env::temp_dir().join(format!("sppm-gpu-view-names-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("box.toml");
        assert_eq!(free_names(&scene).exr, dir.join("box-view-1.exr"));
        std::fs::write(dir.join("box-view-1.png"), b"").unwrap();
        assert_eq!(free_names(&scene).toml, dir.join("box-view-2.toml"));
        std::fs::write(dir.join("box-view-2.toml"), b"").unwrap();
        assert_eq!(free_names(&scene).png, dir.join("box-view-3.png"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_mitsuba_scene_saves_the_image_alone() {
        let dir = std::env::temp_dir().join(format!("sppm-gpu-view-xml-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = Rgb32Image { width: 2, height: 1, pixels: vec![[0.5; 3]; 2] };
        let saved = save(&dir.join("cbox.xml"), &image, None).unwrap();
        assert!(saved.exr.exists() && saved.png.exists());
        assert!(!saved.toml.exists(), "no TOML for an XML scene");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_scene_text_loads_with_the_view_settings() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
        let original = std::fs::read_to_string(&path).unwrap();
        let mut scene = sppm_gpu::scene::load(&path).unwrap();
        scene.camera.position = glam::Vec3::new(0.123_456_79, 1.1, 3.3);
        scene.render.method = Method::PtNee;
        scene.render.width = 64;
        scene.render.radius = Some(0.012_345_679);
        scene.render.time_limit = Some(5.0);
        let text = scene_text(&original, &scene.camera, &scene.render, 7).unwrap();
        let dir = std::env::temp_dir().join(format!("sppm-gpu-view-text-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let saved = dir.join("saved.toml");
        std::fs::write(&saved, &text).unwrap();
        let loaded = sppm_gpu::scene::load(&saved).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(loaded.camera.position, scene.camera.position, "f32 values come back exactly");
        assert_eq!(loaded.render.method, Method::PtNee);
        assert_eq!((loaded.render.width, loaded.render.iterations), (64, 7));
        assert_eq!(loaded.render.radius, scene.render.radius);
        assert_eq!(loaded.render.time_limit, None);
        assert_eq!(loaded.shapes.len(), scene.shapes.len());
        assert!(text.contains("alpha = 0.6667\n"), "short decimals: {text}");
    }

    #[test]
    fn floats_read_back_exactly() {
        let mut x = 1.0e-7f32;
        while x < 1.0e7 {
            for v in [x, -x, x * 1.000_123_5] {
                let toml::Value::Float(f) = float(v) else { panic!() };
                assert_eq!(f as f32, v);
            }
            x *= 1.37;
        }
    }
}
