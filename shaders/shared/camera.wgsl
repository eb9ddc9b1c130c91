// Primary rays: a point on the image plane around the pixel's centre, drawn from the pixel
// filter's density (Frame.pixel_filter), through a pinhole or a thin lens.

struct Ray {
    o: vec3f,
    d: vec3f,
}

// The pixel filters a kernel handles, besides the box: pipeline-overridable, false where the
// scene's filter is another (src/integrators/filter.rs), so that the box costs nothing.
override USES_TENT_FILTER: bool = true;
override USES_GAUSSIAN_FILTER: bool = true;

// Offset with density max(0, 1 - |x| / radius) / radius, by inverting its CDF (pbrt-v4's
// SampleTent): (1 + x / r)^2 / 2 = u below 0, 1 - (1 - x / r)^2 / 2 = u above.
fn sample_tent(u: f32, radius: f32) -> f32 {
    if u < 0.5 {
        return radius * (sqrt(2.0 * u) - 1.0);
    }
    return radius * (1.0 - sqrt(2.0 - 2.0 * u));
}

// C_j of the gaussian's table (Frame.filter_cdf), for j in 1..=FILTER_TABLE_SIZE.
fn gaussian_filter_cdf(j: u32) -> f32 {
    return frame.filter_cdf[(j - 1u) / 4u][(j - 1u) % 4u];
}

// Mitsuba 3's gaussian in standard deviations, unnormalized: exp(-t^2 / 2) - exp(-8).
fn gaussian_filter(t: f32) -> f32 {
    return max(0.0, exp(-0.5 * t * t) - exp(-8.0));
}

// Offset with Mitsuba 3's gaussian density (standard deviation `stddev`, cut off at 4), by
// inverting the CDF of the table: u < 1/2 goes left, the table giving the mass within
// |x|, so the map from u to x stays monotonic. The table holds each interval's exact mass;
// within an interval the density is taken as linear between the filter's values at its
// ends, sampled exactly (pbrt-v4's SampleLinear). That differs from the filter by at most
// h^2 / 8 of its peak, h = 4 / FILTER_TABLE_SIZE: 3e-5.
fn sample_gaussian_filter(u: f32, stddev: f32) -> f32 {
    let c = abs(2.0 * u - 1.0);
    // The interval [t_i, t_i+1) holding c: the largest i with C_i <= c, in 8 halvings.
    var i = 0u;
    for (var step = FILTER_TABLE_SIZE / 2u; step > 0u; step /= 2u) {
        if gaussian_filter_cdf(i + step) <= c {
            i += step;
        }
    }
    let c0 = select(0.0, gaussian_filter_cdf(max(i, 1u)), i > 0u);
    let c1 = gaussian_filter_cdf(i + 1u);
    // c1 > c >= c0 but where c = 1 (u = 0) and the last masses round away in f32.
    let v = select(0.0, clamp((c - c0) / (c1 - c0), 0.0, 1.0), c1 > c0);
    let h = 4.0 / f32(FILTER_TABLE_SIZE);
    // SampleLinear(v, a, b) = v (a + b) / (a + sqrt(lerp(v, a^2, b^2))); a > 0 on [0, 4).
    let a = gaussian_filter(h * f32(i));
    let b = gaussian_filter(h * f32(i + 1u));
    let x = min(v * (a + b) / (a + sqrt(mix(a * a, b * b, v))), 1.0);
    let t = h * (f32(i) + x);
    return select(t, -t, u < 0.5) * stddev;
}

// A camera sample's offset from its pixel's centre, in pixels, from uniform u: one number
// each for x and y, through the inverse CDF of the filter, so each sample has weight 1
// and a pixel converges to the filter-weighted mean of the radiance about its centre
// (filter importance sampling, pbrt-v4 sec. 8.8.3), as Mitsuba's weighted splatting does.
fn sample_filter(u: vec2f) -> vec2f {
    if USES_TENT_FILTER && frame.pixel_filter == FILTER_TENT {
        return vec2f(sample_tent(u.x, frame.filter_width), sample_tent(u.y, frame.filter_width));
    }
    if USES_GAUSSIAN_FILTER && frame.pixel_filter == FILTER_GAUSSIAN {
        return vec2f(sample_gaussian_filter(u.x, frame.filter_width), sample_gaussian_filter(u.y, frame.filter_width));
    }
    return u - 0.5;
}

// The integral of Mitsuba's gaussian over [0, 4] standard deviations, exp(-t^2 / 2) - exp(-8)
// integrated: sqrt(pi / 2) erf(4 / sqrt 2) - 4 exp(-8) (src/integrators/filter.rs tabulates
// the same mass).
const GAUSSIAN_HALF_MASS: f32 = 1.2518929;

// The pixel filter's normalized density at offset x (pixels) from a pixel's centre, per axis:
// the density sample_filter draws camera samples from, and the weight of a splatted sample.
fn filter_density(x: f32) -> f32 {
    if USES_TENT_FILTER && frame.pixel_filter == FILTER_TENT {
        let r = frame.filter_width;
        return max(0.0, 1.0 - abs(x) / r) / r;
    }
    if USES_GAUSSIAN_FILTER && frame.pixel_filter == FILTER_GAUSSIAN {
        let sigma = frame.filter_width;
        return gaussian_filter(x / sigma) / (2.0 * GAUSSIAN_HALF_MASS * sigma);
    }
    return select(0.0, 1.0, abs(x) <= 0.5);
}

// How far from a pixel's centre the filter reaches, in pixels.
fn filter_radius() -> f32 {
    if USES_TENT_FILTER && frame.pixel_filter == FILTER_TENT {
        return frame.filter_width;
    }
    if USES_GAUSSIAN_FILTER && frame.pixel_filter == FILTER_GAUSSIAN {
        return 4.0 * frame.filter_width;
    }
    return 0.5;
}

// The ray through pixel (px, py) of this renderer's rows: row py + frame.row_offset of the
// image. Draws four numbers from rng, lens or not, filter or not, so that what follows sees
// the same stream either way.
fn camera_ray(px: u32, py: u32, rng: ptr<function, Rng>) -> Ray {
    let jitter = rng_next2(rng);
    return camera_ray_at(px, py + frame.row_offset, jitter, rng);
}

// The ray through pixel (px, row) of the whole image, `jitter` its position in the pixel from
// the box's corner, drawing the lens's two numbers from rng. Raster position: the box's, the
// pixel's corner plus jitter, also where samples are splatted through a wide filter
// (frame.filter_reach > 0); under filter importance sampling, the pixel's centre plus an
// offset drawn from the filter. Samples of a wide filter may fall outside the image: they are
// rays through the image plane beyond its edge.
fn camera_ray_at(px: u32, row: u32, jitter: vec2f, rng: ptr<function, Rng>) -> Ray {
    let corner = vec2f(f32(px), f32(row));
    var raster = corner + jitter;
    let wide = (USES_TENT_FILTER && frame.pixel_filter == FILTER_TENT) || (USES_GAUSSIAN_FILTER && frame.pixel_filter == FILTER_GAUSSIAN);
    if wide && frame.filter_reach == 0u {
        raster = corner + 0.5 + sample_filter(jitter);
    }
    // The image plane at distance 1: cam_right and cam_up span half its width and height.
    let sx = 2.0 * raster.x / f32(frame.width) - 1.0;
    let sy = 1.0 - 2.0 * raster.y / f32(frame.image_height);
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

// The rows of camera samples a pass traces, [first, end) of the whole image: this renderer's
// rows and, where samples are splatted through a wide filter (frame.filter_reach > 0), the
// filter's reach beyond them within the image.
fn splat_rows() -> vec2u {
    let first = frame.row_offset - min(frame.filter_reach, frame.row_offset);
    return vec2u(first, min(frame.row_offset + frame.height + frame.filter_reach, frame.image_height));
}
