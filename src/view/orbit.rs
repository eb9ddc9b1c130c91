//! Camera moves of the preview window: orbit about the look-at point, pan, and dolly.

use glam::Quat;
#[cfg(test)]
use glam::Vec3;
use sppm_gpu::scene::Camera;

/// Closest the view direction may come to the up axis, degrees: an orbit stops there instead
/// of flipping over the pole.
const POLE_MARGIN_DEGREES: f32 = 2.0;

/// Nearest the camera may come to the look-at point, as a fraction of where it started.
const MIN_DISTANCE_FRACTION: f32 = 0.01;

/// `camera` turned about its look-at point: `yaw` degrees about the up axis (positive turns
/// the camera to its right), then `pitch` degrees about its right axis (positive raises it),
/// stopping short of the up axis.
pub fn orbit(camera: &Camera, yaw: f32, pitch: f32) -> Camera {
    let up = camera.up.normalize();
    let offset = camera.position - camera.look_at;
    let offset = Quat::from_axis_angle(up, yaw.to_radians()) * offset;
    // The angle between the offset and up after the pitch stays within the margin of (0, 180).
    let angle = offset.angle_between(up).to_degrees();
    let margin = POLE_MARGIN_DEGREES;
    let pitch = pitch.clamp(-(180.0 - margin - angle).max(0.0), (angle - margin).max(0.0));
    let right = (-offset).cross(up).normalize_or_zero();
    let offset = Quat::from_axis_angle(right, -pitch.to_radians()) * offset;
    Camera { position: camera.look_at + offset, ..camera.clone() }
}

/// `camera` and its look-at point moved together across the view: `right` and `up` in units
/// of the distance between them.
pub fn pan(camera: &Camera, right: f32, up: f32) -> Camera {
    let forward = camera.look_at - camera.position;
    let distance = forward.length();
    let x = forward.cross(camera.up).normalize_or_zero();
    let y = x.cross(forward).normalize_or_zero();
    let shift = (x * right + y * up) * distance;
    Camera { position: camera.position + shift, look_at: camera.look_at + shift, ..camera.clone() }
}

/// `camera` moved along its view direction so that its distance to the look-at point is
/// multiplied by `factor`, no nearer than a hundredth of `home`'s.
pub fn dolly(camera: &Camera, factor: f32, home: &Camera) -> Camera {
    let offset = camera.position - camera.look_at;
    let least = (home.position - home.look_at).length() * MIN_DISTANCE_FRACTION;
    let distance = (offset.length() * factor).max(least);
    Camera { position: camera.look_at + offset.normalize() * distance, ..camera.clone() }
}

/// The angle between the view direction and the up axis, degrees (for tests).
#[cfg(test)]
fn elevation(camera: &Camera) -> f32 {
    (camera.position - camera.look_at).angle_between(camera.up).to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 1.0, 3.9),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov: 39.3,
            aperture_radius: 0.0,
            focus_distance: 3.9,
            aperture_line: None,
            crop: None,
            medium: None,
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_turns_by_the_angle() {
        let c = camera();
        let turned = orbit(&c, 90.0, 0.0);
        assert!((turned.position - Vec3::new(3.9, 1.0, 0.0)).length() < 1e-5, "{}", turned.position);
        let raised = orbit(&c, 0.0, 30.0);
        assert!((elevation(&raised) - 60.0).abs() < 1e-3, "{}", elevation(&raised));
        assert!(raised.position.y > c.position.y);
        for cam in [turned, raised] {
            assert!(((cam.position - cam.look_at).length() - 3.9).abs() < 1e-5);
            assert_eq!(cam.look_at, c.look_at);
        }
        // Five degrees left, then right, is where it started.
        let back = orbit(&orbit(&c, 5.0, 0.0), -5.0, 0.0);
        assert!((back.position - c.position).length() < 1e-5);
    }

    #[test]
    fn orbit_stops_short_of_the_poles() {
        let c = camera();
        let top = orbit(&c, 0.0, 170.0);
        assert!((elevation(&top) - POLE_MARGIN_DEGREES).abs() < 1e-2, "{}", elevation(&top));
        let bottom = orbit(&c, 0.0, -170.0);
        assert!((elevation(&bottom) - (180.0 - POLE_MARGIN_DEGREES)).abs() < 1e-2, "{}", elevation(&bottom));
        // At the pole it can still come down.
        assert!(elevation(&orbit(&top, 0.0, -10.0)) > elevation(&top) + 9.0);
    }

    #[test]
    fn pan_moves_both_points_and_dolly_keeps_the_direction() {
        let c = camera();
        let p = pan(&c, 0.1, 0.0);
        assert!((p.position - c.position - Vec3::new(0.39, 0.0, 0.0)).length() < 1e-5, "{}", p.position);
        assert_eq!(p.position - p.look_at, c.position - c.look_at);
        let up = pan(&c, 0.0, 0.1);
        assert!((up.look_at - c.look_at - Vec3::new(0.0, 0.39, 0.0)).length() < 1e-5);
        let near = dolly(&c, 0.5, &c);
        assert!((near.position - Vec3::new(0.0, 1.0, 1.95)).length() < 1e-5);
        let nearest = dolly(&c, 1e-6, &c);
        assert!(((nearest.position - nearest.look_at).length() - 0.039).abs() < 1e-5);
    }
}
