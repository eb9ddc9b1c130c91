//! `sppm-gpu convert SCENE -o OUT.toml`: a scene as read (Mitsuba XML, usually) written in our
//! TOML format, so that it renders the same: the settings, camera, materials (`one_sided`),
//! lights and pixel filter as keys, spheres as spheres, and every other shape's world-space
//! triangles as a binary PLY file of its own in `OUT.meshes/` (with the shading normals the
//! reader gave them, which a TOML `smooth` mesh takes from the file, and their texture
//! coordinates), every texture's texels as a linear EXR beside them. What TOML cannot express
//! (a moving shape, a mirrored environment map) is an error naming it, never a different
//! scene. Nothing that exists is overwritten.

use sppm_gpu::image_io::Rgb32Image;
use sppm_gpu::scene::{Named, Phase, PixelFilter, Scene, Texture, TextureFilter, TextureWrap, Triangle};
use sppm_gpu::Error;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// Writes `scene` as `output` (a `.toml` that does not exist yet) and its meshes beside it.
pub fn convert(scene: &Scene, output: &Path) -> Result<(), Error> {
    let fail = |message: String| Error::Setting(format!("{}: {message}", output.display()));
    if !output.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return Err(fail("the output of convert is a .toml file".into()));
    }
    let meshes = mesh_dir(output);
    if output.exists() || meshes.exists() {
        return Err(fail(format!("{} or {} exists already: convert writes new files only", output.display(), meshes.display())));
    }
    let (doc, ply_files, images) = document(scene, &meshes).map_err(fail)?;
    let text = toml::to_string(&doc).map_err(|e| fail(e.to_string()))?;
    let made_meshes = !ply_files.is_empty() || !images.is_empty();
    let written = (|| {
        if made_meshes {
            std::fs::create_dir(&meshes).map_err(|e| fail(format!("{}: {e}", meshes.display())))?;
        }
        for (path, bytes) in &ply_files {
            write_new(path, bytes)?;
        }
        // In the folder just made: nothing there to overwrite.
        for (path, image) in &images {
            sppm_gpu::image_io::write_exr(path, image).map_err(|e| fail(e.to_string()))?;
        }
        write_new(output, text.as_bytes())
    })();
    // A failure (a full disk) leaves nothing behind to block a retry: the folder and the
    // TOML are ours, made above.
    if written.is_err() {
        if made_meshes {
            let _ = std::fs::remove_dir_all(&meshes);
        }
        let _ = std::fs::remove_file(output);
    }
    written
}

/// `OUT.meshes/` beside `OUT.toml`.
fn mesh_dir(output: &Path) -> PathBuf {
    let stem = output.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    output.with_file_name(format!("{stem}.meshes"))
}

/// Writes `bytes` to `path`, which must not exist.
fn write_new(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write;
    let mut file = std::fs::File::create_new(path).map_err(|e| Error::Setting(format!("{}: {e}", path.display())))?;
    file.write_all(bytes).and_then(|()| file.sync_all()).map_err(|e| Error::Setting(format!("{}: {e}", path.display())))
}

/// An f32 as a TOML float that reads back to the same f32: the shortest decimal that does
/// (`0.8`, not `0.800000011920929`), unless the loader's path (decimal to f64 to f32) would
/// round it twice to another f32; then the f32's exact value.
fn float(x: f32) -> Value {
    let shortest: f64 = x.to_string().parse().unwrap_or(f64::NAN);
    Value::Float(if shortest as f32 == x { shortest } else { x as f64 })
}

/// Every float of `value` that is an f32 (the keys a material or light wrote) as [`float`]
/// writes it.
fn shortest_floats(value: &mut Value) {
    match value {
        Value::Float(x) if (*x as f32) as f64 == *x => *value = float(*x as f32),
        Value::Array(items) => items.iter_mut().for_each(shortest_floats),
        Value::Table(t) => t.iter_mut().for_each(|(_, v)| shortest_floats(v)),
        _ => {}
    }
}

fn vec3(v: glam::Vec3) -> Value {
    Value::Array(v.to_array().iter().map(|&x| float(x)).collect())
}

/// A file to write: its path and bytes.
type File = (PathBuf, Vec<u8>);

/// A texture's texels to write as a linear EXR: its path and image.
type Image = (PathBuf, Rgb32Image);

/// A material's `texture` value: a table naming texture `index`'s texels, written (once) as
/// a linear float EXR in `meshes` (its values kept bit for bit, whatever the file they came
/// from, a procedural checkerboard too), with its filter, wrap mode and uv transform.
fn texture_value(texture: &Texture, index: u32, meshes: &Path, images: &mut Vec<Image>) -> Value {
    let name = format!("texture-{index}.exr");
    let path = meshes.join(&name);
    if !images.iter().any(|(p, _)| *p == path) {
        let pixels = texture.texels.iter().map(|t| t.to_array()).collect();
        images.push((path, Rgb32Image { width: texture.width, height: texture.height, pixels }));
    }
    let dir = meshes.file_name().map_or_else(|| "meshes".into(), |n| n.to_string_lossy().into_owned());
    let mut t = Table::new();
    t.insert("file".into(), Value::String(format!("{dir}/{name}")));
    let filter = if texture.filter == TextureFilter::Nearest { "nearest" } else { "bilinear" };
    t.insert("filter".into(), Value::String(filter.into()));
    let wrap = match texture.wrap {
        TextureWrap::Repeat => "repeat",
        TextureWrap::Mirror => "mirror",
        TextureWrap::Clamp => "clamp",
    };
    t.insert("wrap".into(), Value::String(wrap.into()));
    let [a, c, b, d, tx, ty] = texture.to_uv.to_cols_array();
    let row = |r: [f32; 3]| Value::Array(r.iter().map(|&x| float(x)).collect());
    t.insert("uv_transform".into(), Value::Array(vec![row([a, b, tx]), row([c, d, ty])]));
    Value::Table(t)
}

/// The TOML document, the PLY files of `scene`'s meshes and the images of its textures.
fn document(scene: &Scene, meshes: &Path) -> Result<(Table, Vec<File>, Vec<Image>), String> {
    let mut images = Vec::new();
    let mut doc = Table::new();
    let r = &scene.render;
    let mut render = Table::new();
    let int = |v: u32| Value::Integer(v as i64);
    render.insert("width".into(), int(r.width));
    render.insert("height".into(), int(r.height));
    render.insert("method".into(), Value::String(r.method.name().into()));
    render.insert("iterations".into(), int(r.iterations));
    // Work per pass the scene left to the device stays left to it.
    if r.work_given.spp {
        render.insert("spp".into(), int(r.spp));
    }
    if r.work_given.photons {
        render.insert("photons".into(), int(r.photons));
    }
    if let Some(radius) = r.radius {
        render.insert("radius".into(), float(radius));
    }
    render.insert("alpha".into(), float(r.alpha));
    render.insert("max_depth".into(), int(r.max_depth));
    render.insert("seed".into(), int(r.seed));
    if let Some(t) = r.time_limit {
        render.insert("time_limit".into(), Value::Float(t));
    }
    render.insert("direct".into(), Value::String(r.direct.name().into()));
    if let Some(n) = r.direct_samples {
        render.insert("direct_samples".into(), int(n));
    }
    if let Some(n) = r.light_paths {
        render.insert("light_paths".into(), int(n));
    }
    for (key, share) in [("connect_share", r.connect_share), ("merge_share", r.merge_share)] {
        if let Some(share) = share {
            render.insert(key.into(), float(share));
        }
    }
    // A schedule the scene left to follow its other settings stays left to them.
    if r.radius_schedule_given {
        render.insert("radius_schedule".into(), Value::String(r.radius_schedule.name().into()));
    }
    render.insert("radius_rule".into(), Value::String(r.radius_rule.name().into()));
    render.insert("sampler".into(), Value::String(r.sampler.name().into()));
    match r.filter {
        PixelFilter::Box => {
            render.insert("filter".into(), Value::String("box".into()));
        }
        PixelFilter::Tent { radius } => {
            render.insert("filter".into(), Value::String("tent".into()));
            render.insert("filter_radius".into(), float(radius));
        }
        PixelFilter::Gaussian { stddev } => {
            render.insert("filter".into(), Value::String("gaussian".into()));
            render.insert("filter_stddev".into(), float(stddev));
        }
    }
    doc.insert("render".into(), Value::Table(render));

    let c = &scene.camera;
    let mut camera = Table::new();
    if let Some(crop) = c.crop {
        camera.insert("crop".into(), Value::Array([crop.min.x, crop.min.y, crop.max.x, crop.max.y].map(float).to_vec()));
    }
    camera.insert("position".into(), vec3(c.position));
    camera.insert("look_at".into(), vec3(c.look_at));
    camera.insert("up".into(), vec3(c.up));
    camera.insert("fov".into(), float(c.fov));
    camera.insert("aperture_radius".into(), float(c.aperture_radius));
    camera.insert("focus_distance".into(), float(c.focus_distance));
    let medium_name = |i: u32| Value::String(scene.media[i as usize].name.clone());
    if let Some(m) = c.medium {
        camera.insert("medium".into(), medium_name(m));
    }
    doc.insert("camera".into(), Value::Table(camera));
    if !scene.media.is_empty() {
        let mut media = Table::new();
        for m in &scene.media {
            let mut t = Table::new();
            t.insert("sigma_a".into(), vec3(m.sigma_a));
            t.insert("sigma_s".into(), vec3(m.sigma_s));
            if let Phase::HenyeyGreenstein { g } = m.phase {
                t.insert("phase".into(), Value::String("hg".into()));
                t.insert("g".into(), float(g));
            }
            media.insert(m.name.clone(), Value::Table(t));
        }
        doc.insert("media".into(), Value::Table(media));
    }

    // Material names: the reader's, made unique where two coincide.
    let mut taken = HashSet::new();
    let mut names = Vec::new();
    let mut materials = Table::new();
    for (i, m) in scene.materials.iter().enumerate() {
        let mut name = m.name.clone();
        if !taken.insert(name.clone()) {
            name = format!("{name}#{i}");
            taken.insert(name.clone());
        }
        let mut t = Table::new();
        m.kind.toml_keys(&mut t);
        t.iter_mut().for_each(|(_, v)| shortest_floats(v));
        // The albedo of the kinds that have one, or the texture in its place.
        if let Some((albedo, texture)) = m.kind.albedo() {
            let value = match texture {
                Some(i) => texture_value(&scene.textures[i as usize], i, meshes, &mut images),
                None => vec3(albedo),
            };
            t.insert(if texture.is_some() { "texture" } else { "albedo" }.into(), value);
        }
        if m.one_sided && !m.kind.two_sided_by_nature() {
            t.insert("one_sided".into(), Value::Boolean(true));
        }
        materials.insert(name.clone(), Value::Table(t));
        names.push(name);
    }
    doc.insert("materials".into(), Value::Table(materials));

    let mut shapes = Vec::new();
    let mut files = Vec::new();
    for (i, shape) in scene.shapes.iter().enumerate() {
        let mut t = Table::new();
        if let Some(sphere) = scene.spheres.iter().find(|s| s.shape as usize == i) {
            t.insert("type".into(), Value::String("sphere".into()));
            t.insert("center".into(), vec3(sphere.center));
            t.insert("radius".into(), float(sphere.radius));
            // A Mitsuba sphere's texture frame (its to_world's rotation).
            if let Some(frame) = shape.sphere_frame.filter(|&f| f != sppm_gpu::scene::TOML_SPHERE_FRAME) {
                t.insert("uv_frame".into(), Value::Array([frame.x_axis, frame.y_axis, frame.z_axis].map(vec3).to_vec()));
            }
        } else {
            let triangles: Vec<&Triangle> = scene.triangles.iter().filter(|t| t.shape as usize == i).collect();
            let dir = meshes.file_name().map_or_else(|| "meshes".into(), |n| n.to_string_lossy().into_owned());
            let file = format!("shape-{i}.ply");
            let smooth = triangles.iter().all(|t| t.n.is_some());
            let uvs = triangles.iter().all(|t| t.uv.is_some());
            files.push((meshes.join(&file), ply(&triangles, smooth, uvs)));
            t.insert("type".into(), Value::String("mesh".into()));
            t.insert("file".into(), Value::String(format!("{dir}/{file}")));
            t.insert("smooth".into(), Value::Boolean(smooth));
        }
        t.insert("material".into(), Value::String(names[shape.material as usize].clone()));
        if let Some(e) = shape.emission {
            sppm_gpu::scene::emitter::emission_toml_keys(&mut t, e);
            t.get_mut("emission").into_iter().for_each(shortest_floats);
            if shape.emission_two_sided {
                t.insert("emission_two_sided".into(), Value::Boolean(true));
            }
        }
        if let Some(v) = shape.velocity {
            t.insert("velocity".into(), vec3(v));
        }
        if let Some(m) = shape.interior {
            t.insert("interior".into(), medium_name(m));
        }
        if let Some(m) = shape.exterior {
            t.insert("exterior".into(), medium_name(m));
        }
        shapes.push(Value::Table(t));
    }
    doc.insert("shapes".into(), Value::Array(shapes));

    let mut lights = Vec::new();
    for l in &scene.lights {
        let mut t = Table::new();
        l.kind.toml_keys(&mut t)?;
        t.iter_mut().for_each(|(_, v)| shortest_floats(v));
        lights.push(Value::Table(t));
    }
    if !lights.is_empty() {
        doc.insert("lights".into(), Value::Array(lights));
    }
    Ok((doc, files, images))
}

/// A binary little-endian PLY of `triangles`, three vertices each in order (so that the
/// winding, the front, is kept), with their shading normals when `normals` and their texture
/// coordinates when `uvs`.
fn ply(triangles: &[&Triangle], normals: bool, uvs: bool) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by sppm-gpu convert\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n{}{}element face {}\n\
         property list uchar uint vertex_indices\nend_header\n",
        3 * triangles.len(),
        if normals { "property float nx\nproperty float ny\nproperty float nz\n" } else { "" },
        if uvs { "property float u\nproperty float v\n" } else { "" },
        triangles.len()
    )
    .into_bytes();
    for t in triangles {
        for k in 0..3 {
            out.extend(t.p[k].to_array().iter().flat_map(|x| x.to_le_bytes()));
            if let (true, Some(n)) = (normals, t.n) {
                out.extend(n[k].to_array().iter().flat_map(|x| x.to_le_bytes()));
            }
            if let (true, Some(uv)) = (uvs, t.uv) {
                out.extend(uv[k].to_array().iter().flat_map(|x| x.to_le_bytes()));
            }
        }
    }
    for i in 0..triangles.len() as u32 {
        out.push(3);
        for k in 0..3 {
            out.extend((3 * i + k).to_le_bytes());
        }
    }
    out
}
