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
