//! `sppm-gpu convert`: a Mitsuba XML scene written as TOML (and PLY meshes) loads back to the
//! same scene: settings, camera, materials, lights, spheres and every triangle bit for bit,
//! shading normals to within the last bits of their normalization.

use sppm_gpu::scene::{self, LightKind, Scene};
use std::path::{Path, PathBuf};
use std::process::Command;

fn convert(name: &str, out_dir: &Path) -> (Scene, Scene) {
    let xml = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba").join(name);
    let toml = out_dir.join(name.replace(".xml", ".toml"));
    let out = Command::new(env!("CARGO_BIN_EXE_sppm-gpu")).arg("convert").arg(&xml).arg("-o").arg(&toml).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let read = scene::load(&xml).unwrap();
    let written = scene::load(&toml).unwrap_or_else(|e| panic!("{e}"));
    (read, written)
}

#[test]
fn converted_scenes_load_back_to_the_same_scene() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("convert-tests");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["box.xml", "legacy.xml", "lights.xml"] {
        let (a, b) = convert(name, &dir);
        assert_eq!(a.render, b.render, "{name}");
        assert_eq!(a.camera.position, b.camera.position, "{name}");
        assert_eq!(a.camera.look_at, b.camera.look_at, "{name}");
        assert_eq!(a.camera.up, b.camera.up, "{name}");
        assert_eq!(a.camera.fov, b.camera.fov, "{name}");
        assert_eq!(a.lights.len(), b.lights.len(), "{name}");
        for (l, m) in a.lights.iter().zip(&b.lights) {
            match (&l.kind, &m.kind) {
                (
                    LightKind::Directional { direction: d, irradiance: e },
                    LightKind::Directional { direction: f, irradiance: g },
                ) => {
                    // Normalized again on loading.
                    assert!((*d - *f).length() < 1e-6 && e == g, "{name}: {l:?} {m:?}");
                }
                (k, j) => assert_eq!(k, j, "{name}"),
            }
        }
        assert_eq!(a.spheres, b.spheres, "{name}");
        // TOML keeps its materials in key order: compare each shape's, not the indices.
        assert_eq!(a.materials.len(), b.materials.len());
        assert_eq!(a.shapes.len(), b.shapes.len());
        for (s, t) in a.shapes.iter().zip(&b.shapes) {
            let (m, n) = (&a.materials[s.material as usize], &b.materials[t.material as usize]);
            assert_eq!((&m.kind, m.one_sided, s.emission), (&n.kind, n.one_sided, t.emission), "{name}: {}", m.name);
        }
        assert_eq!(a.triangles.len(), b.triangles.len(), "{name}");
        for (s, t) in a.triangles.iter().zip(&b.triangles) {
            assert_eq!((s.p, s.shape), (t.p, t.shape), "{name}");
            // The loader normalizes the file's normals again: the same to within an ulp or two.
            match (s.n, t.n) {
                (None, None) => {}
                (Some(m), Some(n)) => assert!(m.iter().zip(&n).all(|(m, n)| (*m - *n).length() < 1e-6), "{name}: {m:?} {n:?}"),
                other => panic!("{name}: normals {other:?}"),
            }
        }
    }
    // Nothing is overwritten: a second convert to the same name is refused.
    let xml = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/mitsuba/box.xml");
    let out = Command::new(env!("CARGO_BIN_EXE_sppm-gpu"))
        .arg("convert")
        .arg(&xml)
        .arg("-o")
        .arg(dir.join("box.toml"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("exists already"));
}
