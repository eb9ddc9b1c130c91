// The lights: choosing one in proportion to power, and points on area lights. Photon
// emission and next-event estimation both start here; sample_light and light_pdf are the
// light side of next-event estimation, for the path tracer and SPPM's camera pass alike.

#import envmap
#import cdf

@group(0) @binding(15) var<storage, read> emitters: array<Emitter>;

// The kinds of emitter the scene has (src/gpu/features.rs); see scene.wgsl.
override USES_TRIANGLE_LIGHTS: bool = true;
override USES_SPHERE_LIGHTS: bool = true;
override USES_POINT_LIGHTS: bool = true;
override USES_DIRECTIONAL_LIGHTS: bool = true;
override USES_SPOT_LIGHTS: bool = true;
override USES_ENVIRONMENT: bool = true;

// The environment, always the last emitter; only where USES_ENVIRONMENT.
fn environment() -> Emitter {
    return emitters[frame.emitter_count - 1u];
}

// Index of the emitter whose cdf interval holds u.
fn find_emitter(u: f32) -> u32 {
    return find_cdf(Cdf(CDF_EMITTERS, 0u, vec2u(0u), 0u), frame.emitter_count, u);
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
    if is_sphere_light(e.prim_ref) {
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
    // for a directional light or the environment).
    wi: vec3f,
    dist: f32,
    // Incident radiance over the sample's density: Le / pdf for an area light, I / (d^2 pmf)
    // for a point light (times the falloff for a spot light), E / pmf for a directional one,
    // L / pdf for the environment; zero when the sample is unusable.
    li: vec3f,
    // Solid-angle density of wi, the choice of light included; 0 for a delta light.
    pdf: f32,
    // Where the shadow ray ends: the light point, offset off an area light towards the
    // receiver (pbrt-v4 sec. 6.8.6, SpawnRayTo), or far along wi for a directional light
    // and the environment.
    p_light: vec3f,
    // Cosine between -wi and an area light's normal at the point; 0 for other lights.
    cos_l: f32,
}

// 1 - cos(theta_max) of the cone of directions in which a sphere of radius r at distance d
// (> r) is seen; below 1.5 degrees from its Taylor series sin^2 / 2, which f32 keeps where
// 1 - sqrt(1 - sin^2) would cancel to 0 (pbrt-v4 sec. 6.2.4).
fn sphere_cone(r: f32, d: f32) -> f32 {
    let sin2_max = (r * r) / (d * d);
    if sin2_max < 0.00068523 {
        return 0.5 * sin2_max;
    }
    return 1.0 - sqrt(max(0.0, 1.0 - sin2_max));
}

// A point on sphere `sph` (its centre displaced to the pass's time) uniformly in the cone of
// directions it subtends from p outside it (pbrt-v4 sec. 6.2.4): cos(theta) uniform in
// [cos(theta_max), 1], then the angle alpha at the centre between the axis to p and the
// point, by the law of sines.
fn sample_sphere_cone(sph: Sphere, p: vec3f, u: vec2f) -> LightPoint {
    let center = sph.center + displacement(sph.shape);
    let d = length(p - center);
    let sin2_max = (sph.radius * sph.radius) / (d * d);
    let one_minus_cos = u.x * sphere_cone(sph.radius, d);
    let cos_theta = 1.0 - one_minus_cos;
    let sin2_theta = one_minus_cos * (2.0 - one_minus_cos);
    let cos_alpha = sin2_theta / sqrt(sin2_max) + cos_theta * sqrt(max(0.0, 1.0 - sin2_theta / sin2_max));
    let sin_alpha = sqrt(max(0.0, 1.0 - cos_alpha * cos_alpha));
    let phi = 2.0 * PI * u.y;
    let n = basis((p - center) / d) * vec3f(sin_alpha * cos(phi), sin_alpha * sin(phi), cos_alpha);
    return LightPoint(center + sph.radius * n, n, sph.shape);
}

// Whether emitter reference prim_ref (of an area light) is a sphere, without a load when the
// scene's lights are of one kind.
fn is_sphere_light(prim_ref: u32) -> bool {
    return USES_SPHERE_LIGHTS && (!USES_TRIANGLE_LIGHTS || (prim_ref & SPHERE_BIT) != 0u);
}

// Choose a light in proportion to power (u.x) and a point on it (u.yz), for the receiving
// point p. A sphere light seen from outside is sampled uniformly in the cone it subtends;
// other area lights uniformly by area, the density per unit area area_emitter_density(shape)
// over the Jacobian cos_l / d^2 to solid angle.
fn sample_light(p: vec3f, u: vec3f) -> LightSample {
    let e = emitters[find_emitter(u.x)];
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        let to = e.position - p;
        let dist = length(to);
        return LightSample(to / dist, dist, e.radiance / (dist * dist * e.pmf), 0.0, e.position, 0.0);
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        // A point light whose intensity in direction -wi is I times the falloff.
        let to = e.position - p;
        let dist = length(to);
        let wi = to / dist;
        return LightSample(wi, dist, e.radiance * (spot_falloff(e, -wi) / (dist * dist * e.pmf)), 0.0, e.position, 0.0);
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        let wi = -e.direction;
        // Past the directional light's disk, which encloses the scene.
        let far = 2.0 * e.radius + length(p - e.position);
        return LightSample(wi, 3.4e38, e.radiance / e.pmf, 0.0, p + far * wi, 0.0);
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        // Past the bounding sphere (centre e.position, radius e.radius).
        let far = 2.0 * e.radius + length(p - e.position);
        if is_envmap(e) {
            // By the map's distribution (envmap.wgsl): pdf pmf p(w). Radiance and density
            // as environment_eval finds them from the direction, so that the two strategies
            // weigh a direction on a cell's edge alike whatever its rounding.
            let wi = sample_envmap(e, u.yz).wi;
            let m = envmap_eval(e, wi);
            let pdf = e.pmf * m.pdf;
            let li = select(vec3f(0.0), m.l / pdf, pdf > 0.0);
            return LightSample(wi, 3.4e38, li, pdf, p + far * wi, 0.0);
        }
        // Uniform on the sphere, as Mitsuba 3's `constant` samples: pdf pmf / (4 pi).
        let wi = sample_uniform_sphere(u.yz);
        let pdf = e.pmf * (0.25 * INV_PI);
        return LightSample(wi, 3.4e38, e.radiance / pdf, pdf, p + far * wi, 0.0);
    }
    var l: LightPoint;
    if is_sphere_light(e.prim_ref) && outside_sphere(spheres[e.prim_ref & ~SPHERE_BIT], p) {
        l = sample_sphere_cone(spheres[e.prim_ref & ~SPHERE_BIT], p, u.yz);
    } else {
        l = sample_area_emitter(e, u.yz);
    }
    let to = l.p - p;
    let dist = length(to);
    let wi = to / dist;
    let cos_l = -dot(wi, l.n);
    if cos_l <= 0.0 || dist <= 0.0 {
        return LightSample(wi, dist, vec3f(0.0), 0.0, l.p, cos_l);
    }
    let pdf = light_pdf(p, e.prim_ref, l.shape, dist, cos_l);
    let p_light = l.p + frame.ray_epsilon * l.n;
    return LightSample(wi, dist, shapes[l.shape].emission / pdf, pdf, p_light, cos_l);
}

// Whether p lies outside sphere `sph` (at the pass's time), where cone sampling applies.
fn outside_sphere(sph: Sphere, p: vec3f) -> bool {
    let to = p - (sph.center + displacement(sph.shape));
    return dot(to, to) > sph.radius * sph.radius * 1.0001;
}

// Solid-angle density with which sample_light, called at p, picks a direction that meets
// emitting primitive prim_ref (of shape `shape`) at distance t, where the direction makes
// cosine cos_l with its normal: pmf / (2 pi (1 - cos(theta_max))) in a sphere's cone, and
// pmf / area * t^2 / cos_l for a point chosen by area.
fn light_pdf(p: vec3f, prim_ref: u32, shape: u32, t: f32, cos_l: f32) -> f32 {
    if is_sphere_light(prim_ref) {
        let sph = spheres[prim_ref & ~SPHERE_BIT];
        if outside_sphere(sph, p) {
            // pmf = density * 4 pi r^2.
            let d = length(p - (sph.center + displacement(sph.shape)));
            return area_emitter_density(shape) * 2.0 * sph.radius * sph.radius / sphere_cone(sph.radius, d);
        }
    }
    return area_emitter_density(shape) * t * t / cos_l;
}

// Radiance of the environment from direction w (unit, towards it), and the solid-angle
// density with which sample_light picks w: its pmf times the uniform sphere's 1 / (4 pi) for
// a constant environment, times the map's density for an envmap. Only where USES_ENVIRONMENT.
fn environment_eval(w: vec3f) -> EnvmapEval {
    let e = environment();
    if is_envmap(e) {
        let m = envmap_eval(e, w);
        return EnvmapEval(m.l, e.pmf * m.pdf);
    }
    return EnvmapEval(e.radiance, e.pmf * (0.25 * INV_PI));
}

// Mitsuba 3's spot falloff (src/scene/mod.rs, spot_falloff) in unit direction d leaving spot
// light e: 1 within the beam width of its axis, then linear in the angle theta from the axis
// down to 0 at the cutoff angle (e.radius), over the width e.width; 0 beyond. theta by atan2
// of |d x axis| and d . axis, accurate at every angle, where acos(d . axis) loses half the
// digits near the axis.
fn spot_falloff(e: Emitter, d: vec3f) -> f32 {
    let theta = atan2(length(cross(d, e.direction)), dot(d, e.direction));
    let ramp = (e.radius - theta) / max(e.width, 1e-30);
    return select(select(ramp, 1.0, theta <= e.radius - e.width), 0.0, theta >= e.radius);
}

// A direction leaving spot light e and its weight: intensity times falloff over the
// direction's density, divided by the intensity I on the axis (so the photon's flux is
// I weight / (pmf power_total)). Two parts, chosen by u_part: the cone of full intensity
// (half-angle b = cutoff - width) with probability P_beam = A / Omega, A = 2 pi (1 - cos b) =
// 4 pi sin^2(b / 2) its solid angle and Omega (e.area) the falloff's integral, and the ring of
// falloff otherwise. In the cone directions are uniform (density 1 / A), weight A / P_beam. In
// the ring phi = cutoff - theta is drawn with density 2 phi / w^2 on [0, w] (phi = w sqrt(u),
// w = e.width), proportional to the falloff phi / w; over solid angle that is 2 phi / (w^2 2 pi
// sin(theta)), so the weight, falloff over density over (1 - P_beam), is pi w sin(theta) /
// (1 - P_beam), nearly constant across the ring (sin(theta) from sin(b) to sin(cutoff)). Both
// parts divide by the probability actually used, so rounding in P_beam biases nothing.
struct SpotEmission {
    d: vec3f,
    weight: f32,
}

fn sample_spot_emission(e: Emitter, u_part: f32, u: vec2f) -> SpotEmission {
    let half_beam = 0.5 * max(e.radius - e.width, 0.0);
    let sin_half = sin(half_beam);
    // 1 - cos b, without the cancellation of 1 - cos near b = 0.
    let one_minus_cos_b = 2.0 * sin_half * sin_half;
    let beam_solid_angle = 2.0 * PI * one_minus_cos_b;
    let p_beam = min(beam_solid_angle / e.area, 1.0);
    var cos_theta: f32;
    var sin_theta: f32;
    var weight: f32;
    if u_part < p_beam {
        let one_minus_cos = u.x * one_minus_cos_b;
        cos_theta = 1.0 - one_minus_cos;
        sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
        weight = beam_solid_angle / p_beam;
    } else {
        let theta = e.radius - e.width * sqrt(u.x);
        cos_theta = cos(theta);
        sin_theta = max(sin(theta), 0.0);
        weight = PI * e.width * sin_theta / (1.0 - p_beam);
    }
    let phi = 2.0 * PI * u.y;
    let d = basis(e.direction) * vec3f(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
    return SpotEmission(d, weight);
}
