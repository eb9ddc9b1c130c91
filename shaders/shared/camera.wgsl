// Primary rays: a uniform point in the pixel's square (box filter), through a pinhole or a
// thin lens.

struct Ray {
    o: vec3f,
    d: vec3f,
}

// The ray through pixel (px, py) of this renderer's rows: row py + frame.row_offset of the
// image. Draws four numbers from rng, lens or not, so that what
// follows sees the same stream either way.
fn camera_ray(px: u32, py: u32, rng: ptr<function, Rng>) -> Ray {
    // The image plane at distance 1: cam_right and cam_up span half its width and height.
    let jitter = rng_next2(rng);
    let sx = 2.0 * (f32(px) + jitter.x) / f32(frame.width) - 1.0;
    let sy = 1.0 - 2.0 * (f32(py + frame.row_offset) + jitter.y) / f32(frame.image_height);
    let dir_pinhole = frame.cam_forward + sx * frame.cam_right + sy * frame.cam_up;
    let lens_u = rng_next2(rng);
    if frame.lens_radius > 0.0 {
        // Thin lens: aim through the point that the pinhole ray meets on the focal plane.
        let lens = frame.lens_radius * sample_disk(lens_u);
        let focus = frame.cam_position + frame.focus_distance * dir_pinhole;
        let o = frame.cam_position + lens.x * normalize(frame.cam_right) + lens.y * normalize(frame.cam_up);
        return Ray(o, normalize(focus - o));
    }
    return Ray(frame.cam_position, normalize(dir_pinhole));
}
