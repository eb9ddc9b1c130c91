// Light leaving the emitters: a light chosen in proportion to power and a photon leaving it,
// for SPPM's photon pass and the light subpaths of the light tracer. Each emitter kind's own
// sampling is in lights.wgsl (and envmap.wgsl).

#import types
#import rng
#import sampling
#import scene
#import lights
#import medium

struct Photon {
    o: vec3f,
    d: vec3f,
    beta: vec3f,
    depth: u32,
    // The medium it travels through (shared/medium.wgsl).
    medium: u32,
    // From an area light: the light's normal where it left (a light tracer connects that
    // point to the camera); zero from the other lights, which no camera sees.
    n: vec3f,
}

// Where environment photons are aimed besides the disk covering the scene: a share of them at
// the disk of `radius` about `centre` facing them; none where share is 0.
struct EnvironmentAim {
    centre: vec3f,
    radius: f32,
    share: f32,
}

// Choose a light in proportion to power and a photon leaving it: from an area light, a point
// on it and a cosine-distributed direction from its front; from a point light, a uniform
// direction; from a spot light, a direction in its cone (sample_spot_emission); from a
// directional light, a point on a disk facing it that covers the scene; from the environment,
// a direction (uniform, or by an envmap's distribution) and a point on such a disk or, with
// `aim`, on a mixture of it and the aim's disk (environment_origin).
// beta = Le cos / (pmf * pdf(position) * pdf(direction)), relative to the total power.
fn emit_photon(rng: ptr<function, Rng>, aim: EnvironmentAim) -> Photon {
    let e = emitters[find_emitter(rng_next(rng))];
    let u_pos = rng_next2(rng);
    let u_dir = rng_next2(rng);
    let scale = 1.0 / (e.pmf * frame.power_total);
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        // I / (1 / 4 pi)
        return Photon(e.position, sample_uniform_sphere(u_dir), e.radiance * (4.0 * PI * scale), 0u, CAMERA_MEDIUM, vec3f(0.0));
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        let s = sample_spot_emission(e, u_pos.x, u_dir);
        return Photon(e.position, s.d, e.radiance * (s.weight * scale), 0u, CAMERA_MEDIUM, vec3f(0.0));
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        // E / (1 / disk area)
        let b = basis(e.direction);
        let q = e.radius * sample_disk(u_pos);
        let p = e.position + b[0] * q.x + b[1] * q.y;
        return Photon(p, e.direction, e.radiance * (e.area * scale), 0u, CAMERA_MEDIUM, vec3f(0.0));
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        // Arriving from w, uniform on the sphere, through a point uniform on the disk of the
        // bounding sphere's radius R facing w, placed outside the sphere (pbrt-v4 sec.
        // 12.5.3, UniformInfiniteLight::SampleLe): L / ((1 / 4 pi) (1 / pi R^2)); from an
        // envmap, w by its distribution (pbrt-v4 ImageInfiniteLight::SampleLe): L(w) pi R^2 /
        // p(w).
        var w = sample_uniform_sphere(u_dir);
        var flux = e.radiance * (4.0 * PI * e.area * scale);
        if is_envmap(e) {
            let s = sample_envmap(e, u_dir);
            w = s.wi;
            flux = s.l * select(0.0, e.area * scale / s.pdf, s.pdf > 0.0);
        }
        let b = basis(w);
        let o = environment_origin(e, b[0], b[1], u_pos, aim);
        let p = e.position + 1.01 * e.radius * w + b[0] * o.q.x + b[1] * o.q.y;
        return Photon(p, -w, flux * o.weight, 0u, CAMERA_MEDIUM, vec3f(0.0));
    }
    let l = sample_area_emitter(e, u_pos);
    let d = sample_cosine_hemisphere(l.n, u_dir);
    // Le cos / ((1 / area) * (cos / pi))
    let beta = shapes[l.shape].emission * (PI * e.area * scale);
    // Into the shape's exterior medium where it has one, else the camera's.
    var medium = CAMERA_MEDIUM;
    if USES_MEDIA && shapes[l.shape].media != 0xffffffffu {
        medium = shapes[l.shape].media >> 16u;
    }
    return Photon(offset_origin(l.p, l.n, d), d, beta, 0u, medium, l.n);
}

// A point where an environment photon crosses the plane facing w (coordinates in the plane's
// basis b0, b1 about the bounding sphere's centre), and the weight its flux takes for where it
// was drawn: 1 from the disk of radius R covering the scene alone.
struct EnvironmentOrigin {
    q: vec2f,
    weight: f32,
}

// With aim.share = f > 0: with probability f a point on the aim's disk of radius r (the sphere
// about this pass's visible points, for SPPM), otherwise on the disk of radius R covering
// the scene, as without. Its density on the plane is the mixture's, p(q) = f 1[q in
// the small disk] / (pi r^2) + (1 - f) 1[q in the large disk] / (pi R^2), and the photon's
// flux, L pi R^2 / p(w) from the large disk alone, takes the factor 1 / (pi R^2 p(q)) (one-
// sample MIS over the two disks with the balance heuristic): unbiased, as the large disk
// alone reaches every point of the scene, and where the small disk covers the visible points
// its photons cost (r / R)^2 of a whole-disk photon's. A photon from one disk evaluates
// membership of the other (its own by construction, so that a rounding at the rim cannot
// drop it). u.x picks the disk and is stretched back to [0, 1): with f = 0 the point and the
// random numbers are those of the whole disk alone, bit for bit.
fn environment_origin(e: Emitter, b0: vec3f, b1: vec3f, u: vec2f, aim: EnvironmentAim) -> EnvironmentOrigin {
    let f = aim.share;
    let big = e.radius;
    let r = aim.radius;
    if !(f > 0.0) || !(r < big) {
        return EnvironmentOrigin(big * sample_disk(u), 1.0);
    }
    let c = aim.centre - e.position;
    let qc = vec2f(dot(c, b0), dot(c, b1));
    var q: vec2f;
    var in_small = true;
    var in_big = true;
    if u.x < f {
        q = qc + r * sample_disk(vec2f(u.x / f, u.y));
        in_big = dot(q, q) <= big * big;
    } else {
        q = big * sample_disk(vec2f((u.x - f) / (1.0 - f), u.y));
        let dq = q - qc;
        in_small = dot(dq, dq) <= r * r;
    }
    // pi R^2 p(q).
    let ratio = big / r;
    let density = select(0.0, f * ratio * ratio, in_small) + select(0.0, 1.0 - f, in_big);
    return EnvironmentOrigin(q, 1.0 / density);
}

