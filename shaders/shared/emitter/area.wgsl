// Area emitters (EMITTER_AREA; Mitsuba 3's `area`, pbrt-v4's DiffuseAreaLight): the triangles
// and spheres of a shape with an emission, radiance Le leaving each point's front side alike
// in every direction (both sides where the shape's `emits` is EMITS_BOTH: pbrt-v4's
// `twosided`); power average(Le) area pi (twice it from both sides), one emitter a primitive.
// Photons leave a point uniform on the primitive by area, in a cosine-distributed direction
// (from both sides: about a side chosen with probability 1/2).
// Next-event estimation takes a sphere seen from outside uniformly in the cone it subtends,
// and other points uniformly by area, the density over the Jacobian cos_l / d^2 to solid
// angle.
// Parameters (the Emitter record): `prim_ref`, the primitive (a sphere's with SPHERE_BIT);
// `area`, its area; Le is its shape's emission.

#import types
#import sampling
#import scene
#import medium
#import emitter/light_sample

const EMITTER_AREA: u32 = 0u;

// The scene has emitting triangles; emitting spheres (src/scene/emitter/area.rs).
override USES_TRIANGLE_LIGHTS: bool = true;
override USES_SPHERE_LIGHTS: bool = true;

struct LightPoint {
    p: vec3f,
    // Outward normal: the side that emits.
    n: vec3f,
    shape: u32,
}

// Whether emitter reference prim_ref (of an area light) is a sphere, without a load when the
// scene's lights are of one kind.
fn is_sphere_light(prim_ref: u32) -> bool {
    return USES_SPHERE_LIGHTS && (!USES_TRIANGLE_LIGHTS || (prim_ref & SPHERE_BIT) != 0u);
}

// A uniform point on an area emitter's primitive (density 1 / e.area), where its shape is at
// the pass's shutter time.
fn area_point(e: Emitter, u: vec2f) -> LightPoint {
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
// find_emitter + area_point: pmf / area = average(Le) * pi * sides / power_total, the same for
// every primitive of the shape, since emitters are chosen by power = average(Le) area pi sides.
fn area_density(shape: u32) -> f32 {
    return average(shapes[shape].emission) * PI * f32(sides(shape)) / frame.power_total;
}

// The sides an emitting shape's light leaves: 1 or 2.
fn sides(shape: u32) -> u32 {
    return select(1u, 2u, shapes[shape].emits == EMITS_BOTH);
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
fn sphere_cone_point(sph: Sphere, p: vec3f, u: vec2f) -> LightPoint {
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

// Whether p lies outside sphere `sph` (at the pass's time), where cone sampling applies.
fn outside_sphere(sph: Sphere, p: vec3f) -> bool {
    let to = p - (sph.center + displacement(sph.shape));
    return dot(to, to) > sph.radius * sph.radius * 1.0001;
}

// Solid-angle density with which area_sample, called at p, picks a direction that meets
// emitting primitive prim_ref (of shape `shape`) at distance t, where the direction makes
// cosine cos_l with its normal: pmf / (2 pi (1 - cos(theta_max))) in a sphere's cone, and
// pmf / area * t^2 / cos_l for a point chosen by area.
fn area_pdf(p: vec3f, prim_ref: u32, shape: u32, t: f32, cos_l: f32) -> f32 {
    if is_sphere_light(prim_ref) {
        let sph = spheres[prim_ref & ~SPHERE_BIT];
        if outside_sphere(sph, p) {
            // pmf = density * 4 pi r^2.
            let d = length(p - (sph.center + displacement(sph.shape)));
            return area_density(shape) * 2.0 * sph.radius * sph.radius / sphere_cone(sph.radius, d);
        }
    }
    return area_density(shape) * t * t / cos_l;
}

// Area emitter e seen from p: a point on it (u.yz), Le / pdf, nothing from behind it.
fn area_sample(e: Emitter, p: vec3f, u: vec3f) -> LightSample {
    var l: LightPoint;
    if is_sphere_light(e.prim_ref) && outside_sphere(spheres[e.prim_ref & ~SPHERE_BIT], p) {
        l = sphere_cone_point(spheres[e.prim_ref & ~SPHERE_BIT], p, u.yz);
    } else {
        l = area_point(e, u.yz);
    }
    let to = l.p - p;
    let dist = length(to);
    let wi = to / dist;
    // From both sides: the side p sees.
    if sides(l.shape) == 2u && dot(wi, l.n) > 0.0 {
        l.n = -l.n;
    }
    let cos_l = -dot(wi, l.n);
    if cos_l <= 0.0 || dist <= 0.0 {
        return LightSample(wi, dist, vec3f(0.0), 0.0, l.p, cos_l);
    }
    let pdf = area_pdf(p, e.prim_ref, l.shape, dist, cos_l);
    let p_light = l.p + frame.ray_epsilon * l.n;
    return LightSample(wi, dist, shapes[l.shape].emission / pdf, pdf, p_light, cos_l);
}

// A photon leaving area emitter e: Le cos / ((1 / area) (cos / pi)), times 2 from both sides
// (a side with probability 1/2), times `scale`, into its shape's exterior medium where it has
// one, else the camera's.
fn area_emit(e: Emitter, u_pos: vec2f, u_dir: vec2f, scale: f32) -> EmittedPhoton {
    var l = area_point(e, u_pos);
    // From both sides: a side with probability 1/2 (the first number's halves, each
    // stretched back to [0, 1)), and twice the weight.
    var u = u_dir;
    let two = f32(sides(l.shape));
    if two == 2.0 {
        l.n = select(l.n, -l.n, u.x >= 0.5);
        u.x = fract(2.0 * u.x);
    }
    let d = sample_cosine_hemisphere(l.n, u);
    let beta = shapes[l.shape].emission * (PI * e.area * scale * two);
    var medium = CAMERA_MEDIUM;
    if USES_MEDIA && shapes[l.shape].media != 0xffffffffu {
        medium = shapes[l.shape].media >> 16u;
    }
    return EmittedPhoton(offset_origin(l.p, l.n, d), d, beta, medium, l.n);
}

// The MIS densities of area emitter light at a point of shape `shape` leaving (or hit) at
// cosine cos_l to the normal of the side it leaves (EmissionPdfs): the point by area, pmf /
// area (area_density; a sphere's too, whose next-event estimation samples its cone: the
// weights stay a partition of one, Veach 1997 sec. 9.2.2), and a cosine-distributed
// direction, cos_l / pi, half that from both sides (a side with probability 1/2).
fn area_emission_pdfs(shape: u32, cos_l: f32) -> EmissionPdfs {
    let direct_pdf_a = area_density(shape);
    let pdf_w = max(cos_l, 0.0) * INV_PI / f32(sides(shape));
    return EmissionPdfs(direct_pdf_a, direct_pdf_a * pdf_w, cos_l, false, true);
}
