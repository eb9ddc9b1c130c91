// The lights: choosing one in proportion to power, and points on area lights. Photon
// emission and next-event estimation both start here.

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
