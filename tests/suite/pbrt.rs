//! pbrt-v4 scene files (src/scene/pbrt/): directives, parameter types and their mapping onto
//! the scene, read from small texts (CPU only); errors with file and line; and the Cornell box
//! in pbrt-v4's form (tests/scenes/pbrt/) read and rendered as scenes/cornell-box.toml.

use crate::common;
use glam::Vec3;
use sppm_gpu::metrics::compare;
use sppm_gpu::scene::{self, LightKind, MaterialKind, Method, Phase, PixelFilter, Scene, SceneError};
use std::path::PathBuf;

fn dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/scenes/pbrt"))
}

/// `world` after a camera at the origin looking down +z (`Scale -1 1 1`: no mirror), with a
/// point light unless `world` has its own.
fn read(world: &str) -> (Result<Scene, SceneError>, Vec<SceneError>) {
    let light = if world.contains("LightSource") { "" } else { "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\n" };
    let text = format!("Scale -1 1 1\nLookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\"\nWorldBegin\n{light}{world}");
    scene::pbrt::load_str(&text, &dir().join("inline.pbrt"))
}

fn load(world: &str) -> Scene {
    read(world).0.unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str) -> SceneError {
    match scene::pbrt::load_str(text, &dir().join("inline.pbrt")).0 {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-4
}

#[test]
fn cornell_box_reads_as_the_toml_scene() {
    let pbrt = scene::load(&dir().join("cornell-box.pbrt")).unwrap();
    let toml = common::load_scene("cornell-box.toml");
    assert_eq!(pbrt.triangles.len(), toml.triangles.len());
    assert!(close(pbrt.bounds().0, toml.bounds().0) && close(pbrt.bounds().1, toml.bounds().1));
    assert!(close(pbrt.camera.position, toml.camera.position) && (pbrt.camera.fov - toml.camera.fov).abs() < 1e-4);
    let r = &pbrt.render;
    assert_eq!((r.width, r.height, r.method, r.iterations, r.photons, r.max_depth), (256, 256, Method::Sppm, 64, 200_000, 64));
    assert_eq!(r.filter, PixelFilter::Box);
    // The light faces down, as the TOML scene's.
    let light = pbrt.shapes.iter().position(|s| s.emission.is_some()).unwrap() as u32;
    for t in pbrt.triangles.iter().filter(|t| t.shape == light) {
        assert!((t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).y < 0.0);
    }
    assert_eq!(pbrt.shapes[light as usize].emission, Some(Vec3::new(17.0, 12.0, 4.0)));
    // The files it was read from: the scene and its include.
    assert!(pbrt.inputs.iter().any(|p| p.ends_with("cornell-walls.pbrt")));
}

#[test]
fn cornell_box_renders_as_the_toml_scene() {
    if common::gpu().is_none() {
        return;
    }
    let pbrt = scene::load(&dir().join("cornell-box.pbrt")).unwrap();
    let toml = common::load_scene("cornell-box.toml");
    let a = common::render_at(&pbrt, Method::PtNee, 32, 16);
    let b = common::render_at(&toml, Method::PtNee, 32, 16);
    let c = compare(&a, &b, 8).unwrap();
    eprintln!("pbrt against TOML, pt-nee 32x32, 16 spp: {c:?}");
    // The same triangles, materials and light: the same image but for rounding.
    assert!(c.rel_mse < 1e-4, "relMSE {}", c.rel_mse);
    assert!(c.mean_ratio.iter().all(|r| (r - 1.0).abs() < 0.005), "{:?}", c.mean_ratio);
}

#[test]
fn transforms_and_attributes() {
    let s = load(
        "AttributeBegin\n Translate 1 2 3\n Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n\
         AttributeBegin\n Scale 2 2 2\n Rotate 90 0 0 1\n Translate 1 0 0\n Shape \"sphere\"\nAttributeEnd\n\
         TransformBegin\n Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]\n CoordinateSystem \"here\"\nTransformEnd\n\
         AttributeBegin\n CoordSysTransform \"here\"\n ConcatTransform [ 1 0 0 0  0 1 0 0  0 0 1 0  1 0 0 1 ]\n Shape \"sphere\"\nAttributeEnd\n\
         Shape \"sphere\" \"float radius\" 3\n",
    );
    let centres: Vec<(Vec3, f32)> = s.spheres.iter().map(|s| (s.center, s.radius)).collect();
    assert!(close(centres[0].0, Vec3::new(1.0, 2.0, 3.0)) && centres[0].1 == 0.5);
    assert!(close(centres[1].0, Vec3::new(0.0, 2.0, 0.0)) && (centres[1].1 - 2.0).abs() < 1e-5, "{centres:?}");
    assert!(close(centres[2].0, Vec3::new(6.0, 6.0, 7.0)), "{centres:?}");
    // AttributeEnd restored the identity.
    assert!(close(centres[3].0, Vec3::ZERO) && centres[3].1 == 3.0);
    // TransformBegin is pbrt-v4's deprecated form: warned.
    let (_, warnings) = read("TransformBegin\nTransformEnd\n");
    assert!(warnings.iter().any(|w| w.message.contains("deprecated")), "{warnings:?}");
}

#[test]
fn orientation_follows_winding_normals_and_reverse_orientation() {
    let quad = "\"point3 P\" [ 0 0 5  1 0 5  1 1 5 ]";
    let facing = |world: &str| {
        let s = load(world);
        let t = &s.triangles[0];
        (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).normalize()
    };
    assert!(close(facing(&format!("Shape \"trianglemesh\" {quad}")), Vec3::Z));
    assert!(close(facing(&format!("ReverseOrientation\nShape \"trianglemesh\" {quad}")), Vec3::NEG_Z));
    let n = "\"normal N\" [ 0 0 -1  0 0 -1  0 0 -1 ]";
    assert!(close(facing(&format!("Shape \"trianglemesh\" {quad} {n}")), Vec3::NEG_Z));
    // A mirroring transform keeps pbrt's front.
    assert!(close(facing(&format!("Scale -1 1 1\nShape \"trianglemesh\" {quad}")), Vec3::Z));
    // Bilinear patches face dpdu x dpdv; a disk +z.
    let s = load("Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0 ]\nShape \"disk\" \"float radius\" 2");
    assert_eq!(s.triangles.iter().filter(|t| t.shape == 0).count(), 2);
    for t in &s.triangles {
        assert!((t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).z > 0.0);
    }
    let area: f32 =
        s.triangles.iter().filter(|t| t.shape == 1).map(|t| (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).length() / 2.0).sum();
    assert!((area / (4.0 * std::f32::consts::PI) - 1.0).abs() < 1e-3, "{area}");
}

#[test]
fn camera_fov_spans_the_shorter_axis_and_the_world_is_mirrored() {
    let text = |film: &str, mirror: &str| {
        format!(
            "Film \"rgb\" {film}\n{mirror}LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 60\nWorldBegin\n\
             LightSource \"point\"\nShape \"sphere\" \"float radius\" 0.1\n  Translate 1 0 5 Shape \"sphere\"\n"
        )
    };
    let path = dir().join("inline.pbrt");
    let wide = scene::pbrt::load_str(&text("\"integer xresolution\" 200 \"integer yresolution\" 100", "Scale -1 1 1\n"), &path)
        .0
        .unwrap();
    assert_eq!((wide.render.width, wide.render.height), (200, 100));
    assert!((wide.camera.fov - 60.0).abs() < 1e-4);
    let tall = scene::pbrt::load_str(&text("\"integer xresolution\" 100 \"integer yresolution\" 200", "Scale -1 1 1\n"), &path)
        .0
        .unwrap();
    let expected = 2.0 * ((30f32).to_radians().tan() * 2.0).atan().to_degrees();
    assert!((tall.camera.fov - expected).abs() < 1e-3, "{}", tall.camera.fov);
    // pbrt's camera x runs along the image; without the mirror in the file the world is
    // mirrored so that our camera sees pbrt's image.
    assert!(close(wide.spheres[1].center, Vec3::new(1.0, 0.0, 5.0)));
    // A crop window's pixels as pbrt-v4 counts them (single precision: 0.55 of 800 is 440),
    // each pair in either order: (180, 440) to (461, 640).
    for window in ["0.28 0.72 0.55 0.80", "0.72 0.28 0.80 0.55"] {
        let film = format!("\"integer xresolution\" 640 \"integer yresolution\" 800 \"float cropwindow\" [ {window} ]");
        let s = scene::pbrt::load_str(&text(&film, ""), &path).0.unwrap();
        assert_eq!((s.render.width, s.render.height), (281, 200), "{window}");
        let crop = s.camera.crop.expect("a crop window");
        assert!(close(crop.min.extend(0.0), Vec3::new(180.0 / 640.0, 440.0 / 800.0, 0.0)), "{window}: {crop:?}");
        assert!(close(crop.max.extend(0.0), Vec3::new(461.0 / 640.0, 640.0 / 800.0, 0.0)), "{window}: {crop:?}");
    }
    let plain = scene::pbrt::load_str(&text("", ""), &path).0.unwrap();
    assert!(close(plain.spheres[1].center, Vec3::new(-1.0, 0.0, 5.0)), "{:?}", plain.spheres[1]);
    assert_eq!((plain.render.width, plain.render.height), (1280, 720));
}

#[test]
fn materials_map_to_our_families() {
    let s = load(
        "Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.3 0.4 ]\nShape \"sphere\"\n\
         Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.04\nShape \"sphere\"\n\
         Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\nShape \"sphere\"\n\
         MakeNamedMaterial \"coat\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.1 0.1 ] \"float roughness\" 0\n\
         NamedMaterial \"coat\"\nShape \"sphere\"\n\
         Material \"thindielectric\" \"float eta\" 1.33\nShape \"sphere\"\n\
         Material \"interface\"\nShape \"sphere\"\n\
         Material \"conductor\" \"rgb reflectance\" [ 0.9 0.5 0.2 ] \"bool remaproughness\" false \"float roughness\" 0.3\nShape \"sphere\"\n\
         AttributeBegin\nShape \"sphere\"\nAttributeEnd\n\
         Material \"coateddiffuse\" \"float thickness\" 0.2 \"integer maxdepth\" 3\nShape \"sphere\"\n\
         Material \"coateddiffuse\" \"integer maxdepth\" 0\nShape \"sphere\"\n",
    );
    let kind = |i: usize| &s.shape_material(i as u32).kind;
    assert_eq!(kind(0), &MaterialKind::Diffuse { albedo: Vec3::new(0.2, 0.3, 0.4), texture: None });
    let MaterialKind::Conductor { roughness, fresnel: Some(f), .. } = kind(1) else { panic!("{:?}", kind(1)) };
    assert!((roughness - 0.2).abs() < 1e-6 && f.eta.z > f.eta.x, "{roughness} {f:?}");
    assert!(matches!(kind(2), MaterialKind::Dielectric { ior, roughness: 0.0, .. } if (ior - 1.5168).abs() < 1e-4));
    // pbrt-v4's layer: thickness 0.01 and a walk of 10 steps (the base scatters 5 times).
    let layer = |k: &MaterialKind| match *k {
        MaterialKind::Plastic { ior: 1.5, nonlinear: true, albedo, thickness, scatterings, .. } => {
            (albedo, thickness, scatterings)
        }
        _ => panic!("{k:?}"),
    };
    assert_eq!(layer(kind(3)), (Vec3::new(0.5, 0.1, 0.1), 0.01, 5));
    assert!(matches!(kind(3), MaterialKind::Plastic { roughness: 0.0, .. }));
    assert_eq!(layer(kind(8)), (Vec3::splat(0.5), 0.2, 2));
    // A walk of no steps never reaches the base: black, as pbrt-v4 renders it.
    assert_eq!(layer(kind(9)), (Vec3::ZERO, 0.01, 0));
    assert!(matches!(kind(4), MaterialKind::ThinDielectric { ior, .. } if (ior - 1.33).abs() < 1e-6));
    assert_eq!(kind(5), &MaterialKind::Null);
    let MaterialKind::Conductor { roughness, fresnel: Some(f), .. } = kind(6) else { panic!() };
    assert!((roughness - 0.3).abs() < 1e-6 && f.eta == Vec3::ONE);
    // Normal-incidence reflectance of eta 1 and k: the reflectance given.
    let r0 = f.k * f.k / (4.0 + f.k * f.k);
    assert!(close(r0, Vec3::new(0.9, 0.5, 0.2)), "{r0}");
    // Inside an AttributeBegin the material is the one before it; pbrt's default is a diffuse 0.5.
    assert!(matches!(kind(7), MaterialKind::Conductor { .. }));
    assert_eq!(
        load("Shape \"sphere\"").shape_material(0).kind,
        MaterialKind::Diffuse { albedo: Vec3::splat(0.5), texture: None }
    );
}

#[test]
fn textures() {
    let s = load(
        "Texture \"checks\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0 0 ] \"rgb tex2\" [ 0 0 1 ] \"float uscale\" 4 \"float vscale\" 4\n\
         Texture \"grey\" \"spectrum\" \"constant\" \"rgb value\" [ 0.25 0.25 0.25 ]\n\
         Texture \"half\" \"spectrum\" \"scale\" \"texture tex\" \"grey\" \"float scale\" 2\n\
         Texture \"rough\" \"float\" \"constant\" \"float value\" 0.09\n\
         Material \"diffuse\" \"texture reflectance\" \"checks\"\nShape \"trianglemesh\" \"point3 P\" [ 0 0 5  1 0 5  1 1 5 ]\n\
         Material \"diffuse\" \"texture reflectance\" \"half\"\nShape \"sphere\"\n\
         Material \"conductor\" \"texture roughness\" \"rough\"\nShape \"sphere\"\n",
    );
    let MaterialKind::Diffuse { texture: Some(t), .. } = s.shape_material(0).kind else { panic!() };
    let t = &s.textures[t as usize];
    assert_eq!((t.width, t.height), (2, 2));
    assert_eq!(t.texels[0], Vec3::X);
    // The triangle without uv takes pbrt's (0, 0), (1, 0), (1, 1).
    assert_eq!(s.triangles[0].uv.unwrap()[2], glam::Vec2::ONE);
    assert_eq!(s.shape_material(1).kind, MaterialKind::Diffuse { albedo: Vec3::splat(0.5), texture: None });
    assert!(matches!(s.shape_material(2).kind, MaterialKind::Conductor { roughness, .. } if (roughness - 0.3).abs() < 1e-6));
}

#[test]
fn lights() {
    let s = load(
        "LightSource \"point\" \"rgb I\" [ 1 2 3 ] \"point3 from\" [ 0 1 0 ] \"float scale\" 2\n\
         LightSource \"point\" \"blackbody I\" 3000 \"float power\" 100\n\
         LightSource \"spot\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0 -1 0 ] \"float coneangle\" 40 \"float conedelta\" 10\n\
         LightSource \"distant\" \"point3 from\" [ 0 1 0 ] \"point3 to\" [ 0 0 0 ] \"rgb L\" [ 3 3 3 ]\n\
         LightSource \"infinite\" \"rgb L\" [ 0.5 0.5 0.5 ]\n\
         AttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 6500 \"float scale\" 4\nShape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n",
    );
    let LightKind::Point { position, intensity } = s.lights[0].kind else { panic!() };
    assert!(close(position, Vec3::Y) && close(intensity, Vec3::new(2.0, 4.0, 6.0)));
    let LightKind::Point { intensity, .. } = s.lights[1].kind else { panic!() };
    let luminance = 0.2126 * intensity.x + 0.7152 * intensity.y + 0.0722 * intensity.z;
    assert!((luminance - 100.0 / (4.0 * std::f32::consts::PI)).abs() < 0.2, "{intensity}");
    assert!(intensity.x > intensity.z);
    let LightKind::Spot { direction, cutoff_angle, beam_width, .. } = s.lights[2].kind else { panic!() };
    assert!(close(direction, Vec3::NEG_Y) && cutoff_angle == 40.0 && beam_width == 30.0);
    let LightKind::Directional { direction, irradiance } = s.lights[3].kind else { panic!() };
    assert!(close(direction, Vec3::NEG_Y) && irradiance == Vec3::splat(3.0));
    assert_eq!(s.lights[4].kind, LightKind::Constant { radiance: Vec3::splat(0.5) });
    let e = s.shapes[0].emission.unwrap();
    assert!((0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z - 4.0).abs() < 0.05, "{e}");
    assert_eq!(s.shapes[1].emission, None);
}

#[test]
fn integrators_and_samplers() {
    let settings = |header: &str| {
        let text = format!("{header}\nCamera \"perspective\"\nWorldBegin\nLightSource \"point\"\nShape \"sphere\"");
        scene::pbrt::load_str(&text, &dir().join("inline.pbrt"))
    };
    let r = settings("").0.unwrap().render;
    // pbrt-v4's defaults: volpath of depth 5, 16 samples a pixel, 1280x720, a Gaussian filter.
    assert_eq!((r.method, r.max_depth, r.iterations), (Method::PtNee, 5, 16));
    assert_eq!(r.filter, PixelFilter::Gaussian { stddev: 0.5 });
    let r = settings("Integrator \"sppm\" \"float radius\" 0.1 \"integer maxdepth\" 8\nSampler \"independent\" \"integer pixelsamples\" 4\nFilm \"rgb\" \"integer xresolution\" 10 \"integer yresolution\" 10").0.unwrap().render;
    assert_eq!((r.method, r.max_depth, r.iterations, r.photons, r.radius), (Method::Sppm, 8, 4, 100, Some(0.1)));
    assert_eq!(settings("Integrator \"lightpath\"").0.unwrap().render.method, Method::Lt);
    assert_eq!(settings("Integrator \"bdpt\"").0.unwrap().render.method, Method::Bpt);
    let (mlt, warnings) = settings("Integrator \"mlt\"");
    assert_eq!(mlt.unwrap().render.method, Method::PtNee);
    assert!(warnings.iter().any(|w| w.message.contains("pt-nee")));
    let r = settings("Sampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3\nPixelFilter \"triangle\"")
        .0
        .unwrap()
        .render;
    assert_eq!((r.iterations, r.filter), (6, PixelFilter::Tent { radius: 2.0 }));
}

#[test]
fn errors_name_file_line_and_directive_or_parameter() {
    let world = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    let e = error(&format!("{world}Shape \"sphere\" \"float radius\" 1 \"float bogus\" 2\n"));
    assert_eq!((e.line, e.key.as_deref()), (Some(4), Some("bogus")));
    assert!(e.to_string().contains("inline.pbrt:4") && e.message.contains("unused parameter"), "{e}");
    let e = error(&format!("{world}\nFrobnicate 1 2 3\n"));
    assert_eq!((e.line, e.key.as_deref()), (Some(5), Some("Frobnicate")));
    let e = error(&format!("{world}NamedMaterial \"nope\"\n"));
    assert!(e.message.contains("not defined") && e.line == Some(4), "{e}");
    let e = error(&format!("{world}Shape \"loopsubdiv\"\n"));
    assert!(e.key.as_deref() == Some("P") && e.message.contains("not provided"), "{e}");
    let e = error(&format!("{world}Material \"mix\"\n"));
    assert!(e.key.as_deref() == Some("materials") && e.message.contains("mix"), "{e}");
    let e = error(&format!("{world}Shape \"sphere\" \"float radius\" [ 1 2 \n"));
    assert!(e.message.contains("]") && e.line == Some(4), "{e}");
    let e = error(&format!("{world}AttributeEnd\n"));
    assert!(e.message.contains("unmatched"), "{e}");
    let e = error(&format!("{world}AreaLightSource \"diffuse\" \"string filename\" \"a.png\"\n"));
    assert_eq!(e.key.as_deref(), Some("filename"));
    let e = error("WorldBegin\nLightSource \"point\"\nShape \"sphere\"\nAttributeBegin\n");
    assert!(e.message.contains("not ended") && e.line == Some(4), "{e}");
    // In an included file, that file and its line.
    let e = error(&format!("{world}Include \"missing-file.pbrt\"\n"));
    assert!(e.line == Some(4) && e.message.contains("missing-file.pbrt"), "{e}");
    let e = error(&format!("{world}Include \"bad-include.pbrt\"\n"));
    assert!(e.file.ends_with("bad-include.pbrt") && e.line == Some(3), "{e}");
}

#[test]
fn loopsubdiv_is_subdivided_to_the_limit_surface() {
    let s = scene::load(&dir().join("loopsubdiv.pbrt")).unwrap();
    // 8 faces, four of each a level.
    assert_eq!(s.triangles.len(), 8 * 16);
    // The octahedron's vertices end at half their distance (subdiv.rs's test works it out),
    // with the limit surface's normal along the axis.
    for axis in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
        let (t, k) = s
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t, k)))
            .find(|(t, k)| (t.p[*k] - 0.5 * axis).length() < 1e-5)
            .unwrap_or_else(|| panic!("no vertex at {}", 0.5 * axis));
        // pbrt-v4's cross(S, T) over its one-ring walk (which turns clockwise seen from the
        // side a counter-clockwise winding faces) points into this outward-wound octahedron.
        let n = t.n.expect("shading normals")[k];
        assert!(n.dot(axis) < -0.999, "{n} at {axis}");
        assert!((t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]).dot(n) > 0.0, "fronts follow N");
    }
    // Every vertex lies between the limit's extremes, none outside the octahedron.
    assert!(s.triangles.iter().flat_map(|t| t.p).all(|p| p.abs().element_sum() <= 1.0 + 1e-5 && p.length() >= 0.4));
    let world = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    let tri = "\"point3 P\" [ 0 0 0  1 0 0  0 1 0  0 0 1 ]";
    let e = error(&format!("{world}Shape \"loopsubdiv\" \"integer levels\" -1 {tri} \"integer indices\" [ 0 1 2 ]\n"));
    assert_eq!((e.line, e.key.as_deref()), (Some(4), Some("levels")), "{e}");
    // An edge of three faces (two of them run it the same way), named at the parameter's line.
    let e = error(&format!("{world}Shape \"loopsubdiv\" {tri}\n \"integer indices\" [ 0 1 2  1 0 3  0 1 3 ]\n"));
    assert!(e.line == Some(5) && e.key.as_deref() == Some("indices") && e.message.contains("not manifold"), "{e}");
}

#[test]
fn area_light_power() {
    use std::f32::consts::PI;
    let s = scene::load(&dir().join("area-power.pbrt")).unwrap();
    let e: Vec<Vec3> = s.shapes.iter().map(|s| s.emission.unwrap()).collect();
    assert!(close(e[0], Vec3::splat(0.5 * 10.0 / (2.0 * PI))), "{}", e[0]);
    assert!(close(e[1], Vec3::splat(2.0 * 20.0 / (PI * PI))), "{}", e[1]);
    assert!(close(e[2], Vec3::splat(3.0 / (0.75 * PI * PI))), "{}", e[2]);
    assert!(close(e[3], Vec3::splat(0.5 * 10.0 / (2.0 * 2.0 * PI))), "{}", e[3]);
    let two_sided: Vec<bool> = s.shapes.iter().map(|s| s.emission_two_sided).collect();
    assert_eq!(two_sided, [false, false, false, true]);
    // Triangles of different areas would each emit the power: refused, naming the parameter.
    let e = error(
        "Camera \"perspective\"\nWorldBegin\nAreaLightSource \"diffuse\" \"float power\" 1\n\
         Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  2 2 0 ] \"integer indices\" [ 0 1 2  1 3 2 ]\n",
    );
    assert!(e.line == Some(4) && e.key.as_deref() == Some("power") && e.message.contains("differ"), "{e}");
}

#[test]
fn mix_of_amount_zero_or_one_is_that_material() {
    let s = scene::load(&dir().join("mix.pbrt")).unwrap();
    let kind = |shape: usize| &s.materials[s.shapes[shape].material as usize].kind;
    assert!(matches!(kind(0), MaterialKind::Dielectric { ior, .. } if (*ior - 1.33).abs() < 1e-6), "{:?}", kind(0));
    assert!(matches!(kind(1), MaterialKind::Diffuse { albedo, .. } if close(*albedo, Vec3::new(0.8, 0.1, 0.1))), "{:?}", kind(1));
    let defs = "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"b\" \"string type\" \"conductor\"\n";
    let e = error(&format!(
        "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n{defs}Material \"mix\" \"string materials\" [ \"a\" \"b\" ] \"float amount\" 0.3\n"
    ));
    assert!(e.line == Some(6) && e.key.as_deref() == Some("amount") && e.message.contains("at random"), "{e}");
    let e = error(&format!("Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n{defs}Material \"mix\" \"string materials\" [ \"a\" \"c\" ] \"float amount\" 1\n"));
    assert!(e.line == Some(6) && e.message.contains("c: named material not found"), "{e}");
}

#[test]
fn media_and_medium_interfaces() {
    let s = scene::load(&dir().join("media.pbrt")).unwrap();
    assert_eq!(s.media.len(), 2);
    let (fog, water) = (&s.media[0], &s.media[1]);
    assert!(close(fog.sigma_a, Vec3::new(0.02, 0.04, 0.06)) && close(fog.sigma_s, Vec3::splat(0.2)));
    assert_eq!(fog.phase, Phase::Isotropic);
    // pbrt-v4's defaults: sigma_a = sigma_s = 1.
    assert!(close(water.sigma_a, Vec3::ONE) && close(water.sigma_s, Vec3::ONE));
    assert_eq!(water.phase, Phase::HenyeyGreenstein { g: 0.5 });
    assert_eq!(s.camera.medium, Some(0));
    let sides: Vec<_> = s.shapes.iter().map(|s| (s.interior, s.exterior)).collect();
    assert_eq!(sides, [(Some(1), Some(0)), (Some(0), Some(1)), (Some(0), None), (None, None)]);
    let world = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    let e = error(&format!("{world}MediumInterface \"smoke\" \"\"\nShape \"sphere\"\n"));
    assert!(e.line == Some(5) && e.message.contains("smoke: medium not defined"), "{e}");
    let e = error(&format!("{world}MakeNamedMedium \"c\" \"string type\" \"cloud\"\n"));
    assert!(e.line == Some(4) && e.key.as_deref() == Some("type") && e.message.contains("not modelled"), "{e}");
    let e = error(&format!("{world}MakeNamedMedium \"c\" \"string type\" \"homogeneous\" \"rgb Le\" [ 1 1 1 ]\n"));
    assert_eq!(e.key.as_deref(), Some("Le"), "{e}");
    let e = error(&format!("{world}MakeNamedMedium \"c\" \"string type\" \"homogeneous\" \"float g\" 1\n"));
    assert_eq!(e.key.as_deref(), Some("g"), "{e}");
}

#[test]
fn pfm_images_as_pbrt_reads_them() {
    // grid.pfm: 2 x 2, little-endian, its bottom row (0.1 0.2 0.3) (0.4 0.5 0.6) stored first.
    let s = load(
        "Texture \"g\" \"spectrum\" \"imagemap\" \"string filename\" \"grid.pfm\"\n\
         Material \"diffuse\" \"texture reflectance\" \"g\"\nShape \"sphere\"\n",
    );
    let MaterialKind::Diffuse { texture: Some(t), .. } = s.shape_material(0).kind else { panic!() };
    let t = &s.textures[t as usize];
    assert_eq!((t.width, t.height), (2, 2));
    // Row 0 is the top; a float image is linear whatever the encoding says for 8-bit ones.
    assert_eq!(
        *t.texels,
        [Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0), Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.4, 0.5, 0.6)]
    );
}

/// A triangle mesh whose every triangle has no area adds nothing, with a warning naming its
/// line, as pbrt-v4 loads it; as an area light it is refused.
#[test]
fn meshes_without_area_are_warned_and_refused_as_lights() {
    let flat = "Shape \"trianglemesh\" \"point3 P\" [ 0 0 5  1 0 5  2 0 5 ] \"integer indices\" [ 0 1 2 ]\n";
    let (scene, warnings) = read(flat);
    let scene = scene.unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.triangles.is_empty() && scene.shapes.is_empty(), "the empty mesh adds no shape");
    let warning = warnings.iter().find(|w| w.message.contains("no area")).unwrap_or_else(|| panic!("{warnings:?}"));
    assert_eq!(warning.line, Some(6), "{warning}");
    let light = format!("AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 1 1 1 ]\n{flat}AttributeEnd\n");
    let (scene, _) = read(&light);
    let e = scene.expect_err("a light of no area");
    assert!(e.message.contains("nothing to emit from"), "{e}");
    assert_eq!(e.line, Some(7), "{e}");
}

/// `ActiveTransform` and `TransformTimes`: a shape whose transforms at the start and end times
/// differ by a translation moves over the camera's shutter (our `velocity`), from where the
/// shutter opens; motion that rotates or scales, a moving camera, light or instance, and a
/// shutter open outside the transform times are refused, naming the directive.
#[test]
fn motion_from_active_transforms() {
    let s = load(
        "AttributeBegin\n Translate 1 0 0\n ActiveTransform StartTime\n Translate 0 2 0\n ActiveTransform All\n\
         Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n\
         AttributeBegin\n ActiveTransform EndTime\nAttributeEnd\nShape \"sphere\"\n",
    );
    assert!(close(s.spheres[0].center, Vec3::new(1.0, 2.0, 0.0)), "{:?}", s.spheres[0]);
    assert!(close(s.shapes[0].velocity.unwrap(), Vec3::new(0.0, -2.0, 0.0)), "{:?}", s.shapes[0].velocity);
    // AttributeEnd restored both transforms and which of them directives set.
    assert_eq!(s.shapes[1].velocity, None);

    // The times (0, 2), the shutter (0.5, 1.5): the shape from a quarter of the way, at half the
    // displacement over the shutter; a mesh moves whole.
    let timed = |shutter: &str, shape: &str| {
        format!(
            "TransformTimes 0 2\nScale -1 1 1\nCamera \"perspective\" {shutter}\nWorldBegin\nLightSource \"point\"\n\
             ActiveTransform EndTime\nTranslate 4 0 0\nActiveTransform All\n{shape}"
        )
    };
    let text = timed("\"float shutteropen\" 0.5 \"float shutterclose\" 1.5", "Shape \"sphere\"\n");
    let (s, _) = scene::pbrt::load_str(&text, &dir().join("inline.pbrt"));
    let s = s.unwrap();
    assert!(close(s.spheres[0].center, Vec3::new(1.0, 0.0, 0.0)), "{:?}", s.spheres[0]);
    assert!(close(s.shapes[0].velocity.unwrap(), Vec3::new(2.0, 0.0, 0.0)), "{:?}", s.shapes[0].velocity);
    let triangle = "Shape \"trianglemesh\" \"point3 P\" [ 0 0 1  1 0 1  0 1 1 ]\n";
    let (s, _) = scene::pbrt::load_str(&timed("", triangle), &dir().join("inline.pbrt"));
    let s = s.unwrap();
    assert!(close(s.triangles[0].p[0], Vec3::Z) && close(s.shapes[0].velocity.unwrap(), Vec3::new(2.0, 0.0, 0.0)));

    let e = error(&timed("\"float shutterclose\" 3", "Shape \"sphere\"\n"));
    assert!(e.message.contains("shutter") && e.key.as_deref() == Some("Shape \"sphere\""), "{e}");
    let world = "Camera \"perspective\"\nWorldBegin\nLightSource \"point\"\n";
    let e = error(&format!("{world}ActiveTransform StartTime\nRotate 30 0 0 1\nShape \"sphere\"\n"));
    assert!(e.message.contains("rotates or scales") && e.line == Some(6), "{e}");
    let e = error("ActiveTransform EndTime\nTranslate 1 0 0\nCamera \"perspective\"\nWorldBegin\n");
    assert!(e.message.contains("moving camera") && e.line == Some(3), "{e}");
    let e = error(&format!("{world}ActiveTransform EndTime\nTranslate 1 0 0\nLightSource \"point\"\n"));
    assert!(e.message.contains("light that moves") && e.line == Some(6), "{e}");
    let e = error(&format!(
        "{world}ObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\nActiveTransform EndTime\nTranslate 1 0 0\nObjectInstance \"o\"\n"
    ));
    assert!(e.message.contains("object instance that moves"), "{e}");
    // tests/scenes/pbrt/motion.pbrt: times (0, 2), the shutter (0, 1): half of each motion,
    // in our world, which mirrors pbrt's x for its camera (no `Scale -1 1 1` there).
    let s = scene::load(&dir().join("motion.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let v: Vec<Option<Vec3>> = s.shapes.iter().map(|s| s.velocity).collect();
    assert!(
        v[0].is_none() && close(v[1].unwrap(), Vec3::new(-0.5, 0.0, 0.0)) && close(v[2].unwrap(), Vec3::new(0.0, 0.25, 0.0)),
        "{v:?}"
    );
    let e = error(&format!("{world}ActiveTransform Sometimes\n"));
    assert!(e.message.contains("Sometimes") && e.line == Some(4), "{e}");
}
