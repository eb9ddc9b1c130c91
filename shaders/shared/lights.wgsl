// The lights: choosing one in proportion to power, and points on area lights. Photon
// emission and next-event estimation both start here; light_sample and light_pdf are the
// light side of next-event estimation, for the path tracer and SPPM's camera pass alike.

@group(0) @binding(15) var<storage, read> emitters: array<Emitter>;

// The kinds of emitter the scene has (src/gpu/features.rs); see scene.wgsl.
override USES_TRIANGLE_LIGHTS: bool = true;
override USES_SPHERE_LIGHTS: bool = true;
override USES_POINT_LIGHTS: bool = true;
override USES_DIRECTIONAL_LIGHTS: bool = true;

// Index of the emitter whose cdf interval holds u (binary search).
fn find_emitter(u: f32) -> u32 {
    var lo = 0u;
    var hi = frame.emitter_count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if emitters[mid].cdf <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

struct LightPoint {
    p: vec3f,
    // Outward normal: the side that emits.
    n: vec3f,
    shape: u32,
}

// A uniform point on an area emitter's primitive (density 1 / e.area), where its shape is at
// the pass's shutter time.
fn sample_area_emitter(e: Emitter, u: vec2f) -> LightPoint {
    if USES_SPHERE_LIGHTS && (!USES_TRIANGLE_LIGHTS || (e.prim_ref & SPHERE_BIT) != 0u) {
        let s = spheres[e.prim_ref & ~SPHERE_BIT];
        let n = sample_uniform_sphere(u);
        return LightPoint(s.center + s.radius * n + displacement(s.shape), n, s.shape);
    }
    let tri = triangles[e.prim_ref];
    let b = sample_triangle(u);
    let p = tri.p0 + b.x * tri.e1 + b.y * tri.e2 + displacement(tri.shape);
    return LightPoint(p, normalize(cross(tri.e1, tri.e2)), tri.shape);
}

// Density per unit area of choosing a point on an emitting shape's surface by
// find_emitter + sample_area_emitter: pmf / area = average(Le) * pi / power_total, the same
// for every primitive of the shape, since emitters are chosen by power = average(Le) area pi.
fn area_emitter_density(shape: u32) -> f32 {
    return average(shapes[shape].emission) * PI / frame.power_total;
}

// A light sample seen from a receiving point (pbrt-v4 sec. 12.2, LightLiSample).
struct LightSample {
    // Unit direction from the receiver towards the light, and the distance to it (3.4e38
    // for a directional light).
    wi: vec3f,
    dist: f32,
    // Incident radiance over the sample's density: Le / pdf for an area light, I / (d^2 pmf)
    // for a point light, E / pmf for a directional one; zero when the sample is unusable.
    li: vec3f,
    // Solid-angle density of wi, the choice of light included; 0 for a delta light.
    pdf: f32,
    // Where the shadow ray ends: the light point, offset off an area light towards the
    // receiver (pbrt-v4 sec. 6.8.6, SpawnRayTo), or far along wi for a directional light.
    p_light: vec3f,
}

// Choose a light in proportion to power (u.x) and a point on it (u.yz), for the receiving
// point p. Area lights are sampled uniformly by area: the density per unit area
// area_emitter_density(shape), over the Jacobian cos_l / d^2 to solid angle.
fn sample_light(p: vec3f, u: vec3f) -> LightSample {
    let e = emitters[find_emitter(u.x)];
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        let to = e.position - p;
        let dist = length(to);
        return LightSample(to / dist, dist, e.radiance / (dist * dist * e.pmf), 0.0, e.position);
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        let wi = -e.direction;
        // Past the directional light's disk, which encloses the scene.
        let far = 2.0 * e.radius + length(p - e.position);
        return LightSample(wi, 3.4e38, e.radiance / e.pmf, 0.0, p + far * wi);
    }
    let l = sample_area_emitter(e, u.yz);
    let to = l.p - p;
    let dist = length(to);
    let wi = to / dist;
    let cos_l = -dot(wi, l.n);
    if cos_l <= 0.0 || dist <= 0.0 {
        return LightSample(wi, dist, vec3f(0.0), 0.0, l.p);
    }
    let pdf = light_pdf(l.shape, dist, cos_l);
    let p_light = l.p + frame.ray_epsilon * l.n;
    return LightSample(wi, dist, shapes[l.shape].emission / pdf, pdf, p_light);
}

// Solid-angle density with which sample_light picks a direction that meets emitting shape
// `shape` at distance t, where the direction makes cosine cos_l with its normal.
fn light_pdf(shape: u32, t: f32, cos_l: f32) -> f32 {
    return area_emitter_density(shape) * t * t / cos_l;
}
