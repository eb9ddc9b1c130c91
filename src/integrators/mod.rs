//! Integrators: SPPM now; the path tracers share the scene, camera and kernels' shared code.

pub mod sppm;

pub use sppm::Sppm;

use crate::gpu::types::Frame;
use crate::scene::Scene;

/// The camera part of [`Frame`]: position and the image-plane basis at distance 1
/// (`cam_right` spans half the image width, `cam_up` half its height).
pub fn camera_frame(scene: &Scene) -> Frame {
    let c = &scene.camera;
    let forward = (c.look_at - c.position).normalize();
    let right = forward.cross(c.up).normalize();
    let up = right.cross(forward);
    let tan_half = (c.fov.to_radians() * 0.5).tan();
    let aspect = scene.render.width as f32 / scene.render.height as f32;
    Frame {
        cam_position: c.position.into(),
        lens_radius: c.aperture_radius,
        cam_right: (right * tan_half * aspect).into(),
        focus_distance: c.focus_distance,
        cam_up: (up * tan_half).into(),
        width: scene.render.width,
        cam_forward: forward.into(),
        height: scene.render.height,
        spp: scene.render.spp,
        seed: scene.render.seed,
        max_depth: scene.render.max_depth,
        alpha: scene.render.alpha,
        ..Frame::default()
    }
}

/// The shutter time of pass `pass` in [0, 1): the base-2 radical inverse of the pass index
/// (van der Corput), rotated by an offset drawn from the seed (Cranley-Patterson rotation).
/// Any run of passes from the first covers the shutter evenly, so a render stopped early by
/// a time limit still averages over the whole shutter.
pub fn shutter_time(seed: u32, pass: u32) -> f32 {
    let radical_inverse = pass.reverse_bits() as f64 / 4294967296.0;
    // SplitMix-style hash of the seed to an offset in [0, 1).
    let mut z = (seed as u64).wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    let offset = (z >> 11) as f64 / (1u64 << 53) as f64;
    let t = (radical_inverse + offset).fract() as f32;
    // Rounding to f32 can give exactly 1.
    t.min(1.0 - f32::EPSILON / 2.0)
}
