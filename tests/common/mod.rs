//! Shared by the GPU tests: a device, or a clear reason there is none.
#![allow(dead_code)]

mod rng;
pub mod scene_text;
#[allow(unused_imports)]
pub use rng::Rng;

use sppm_gpu::gpu::GpuContext;
use sppm_gpu::scene::Scene;
use std::path::PathBuf;

/// A device for a GPU test. Without one the test is skipped with a message, except under CI
/// (`CI=true`), where a missing adapter fails the test.
pub fn gpu() -> Option<GpuContext> {
    match GpuContext::new() {
        Ok(ctx) => Some(ctx),
        Err(e) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("CI=true and no GPU adapter: {e}");
            }
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

pub fn load_scene(name: &str) -> Scene {
    sppm_gpu::scene::load(&scene_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

pub fn reference(name: &str) -> sppm_gpu::image_io::Rgb32Image {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/references").join(name);
    sppm_gpu::image_io::read_exr(&path).unwrap_or_else(|e| panic!("{e}"))
}
