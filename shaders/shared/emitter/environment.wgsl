// The environment (EMITTER_ENVIRONMENT; Mitsuba 3's `constant` and `envmap`, pbrt-v4's
// UniformInfiniteLight and ImageInfiniteLight): radiance L(w) from every direction at
// infinity, constant or from an equirectangular image (shared/envmap.wgsl). A scene has at
// most one, the last emitter. Its photons cross the disk of radius R that covers the scene's
// bounding sphere, from every direction; power pi R^2 times the integral of average(L) over
// the sphere of directions.
// Parameters (the Emitter record): `prim_ref`, an envmap's entries in `texels` (NO_TEXTURE for
// a constant one); `radiance`, the constant L or the map's scale; `position` and `radius`, the
// bounding sphere's centre and R; `area`, pi R^2.

#import types
#import sampling
#import medium
#import envmap
#import emitter/light_sample

const EMITTER_ENVIRONMENT: u32 = 4u;

// The scene has an environment (src/scene/emitter/environment.rs).
override USES_ENVIRONMENT: bool = true;

// Environment e seen from p: a direction by the map's distribution (envmap.wgsl), density
// pmf p(w), or uniform on the sphere, as Mitsuba 3's `constant` samples, density pmf / (4 pi);
// the shadow ray ends past the bounding sphere. An envmap's radiance and density are
// envmap_eval's from the direction, so that the two strategies weigh a direction on a cell's
// edge alike whatever its rounding.
fn environment_sample(e: Emitter, p: vec3f, u: vec3f) -> LightSample {
    let far = 2.0 * e.radius + length(p - e.position);
    if is_envmap(e) {
        let wi = sample_envmap(e, u.yz).wi;
        let m = envmap_eval(e, wi);
        let pdf = e.pmf * m.pdf;
        let li = select(vec3f(0.0), m.l / pdf, pdf > 0.0);
        return LightSample(wi, 3.4e38, li, pdf, p + far * wi, 0.0);
    }
    let wi = sample_uniform_sphere(u.yz);
    let pdf = e.pmf * (0.25 * INV_PI);
    return LightSample(wi, 3.4e38, e.radiance / pdf, pdf, p + far * wi, 0.0);
}

// Radiance of environment e from direction w (unit, towards it), and the solid-angle density
// with which environment_sample picks w.
fn environment_radiance(e: Emitter, w: vec3f) -> EnvmapEval {
    if is_envmap(e) {
        let m = envmap_eval(e, w);
        return EnvmapEval(m.l, e.pmf * m.pdf);
    }
    return EnvmapEval(e.radiance, e.pmf * (0.25 * INV_PI));
}

// The visible points a share of an environment's photons is aimed at (SPPM, photon_pass.wgsl):
// that share `fraction` (frame.env_aim; 0 for none), the points' largest radius and the box of
// their positions.
struct EnvironmentAim {
    fraction: f32,
    max_radius: f32,
    lo: vec3f,
    hi: vec3f,
}

// The aim of the bidirectional methods' light subpaths (light_trace.wgsl): the share
// frame.env_aim of them drawn through the sphere around what the camera sees, the record's
// `direction` (its centre) and `width` (its radius; 0 where not aimed:
// src/gpu/scene_buffers.rs, camera_sees).
fn environment_light_aim(e: Emitter) -> EnvironmentAim {
    return EnvironmentAim(select(0.0, frame.env_aim, e.width > 0.0), e.width, e.direction, e.direction);
}

// pi R^2 times the density, on the plane facing w (unit, towards the environment), of the
// point where the line through x along w crosses it, as environment_origin draws it with
// `aim`: 1 without aim, else f (R / r)^2 inside the small disk plus (1 - f) inside the large
// one. x is any point of the line (a photon's origin, a vertex that samples or escapes to w).
fn environment_disk_density(e: Emitter, w: vec3f, x: vec3f, aim: EnvironmentAim) -> f32 {
    let f = aim.fraction;
    let big = e.radius;
    if !(f > 0.0) || !(aim.max_radius > 0.0) {
        return 1.0;
    }
    let r = 0.5 * length(aim.hi - aim.lo) + aim.max_radius;
    if !(r < big) {
        return 1.0;
    }
    // Each disk's centre is its sphere's centre seen along w: the line's distance from it.
    let to_small = x - 0.5 * (aim.lo + aim.hi);
    let s = to_small - dot(to_small, w) * w;
    let to_big = x - e.position;
    let b = to_big - dot(to_big, w) * w;
    let ratio = big / r;
    return select(0.0, f * ratio * ratio, dot(s, s) <= r * r) + select(0.0, 1.0 - f, dot(b, b) <= big * big);
}

// The MIS densities of environment e (EmissionPdfs) for the direction w towards it (unit),
// along the line through x: a light at infinity's, not in area measure (SmallVCM's
// BackgroundLight): next-event estimation's solid-angle density of w (environment_radiance's,
// its choice included), and a photon's, that density times its point's on the disk
// (environment_disk_density over the disk's area e.area: environment_emit with `aim`, as the
// bidirectional methods' light subpaths leave it); not delta.
fn environment_emission_pdfs(e: Emitter, w: vec3f, x: vec3f, aim: EnvironmentAim) -> EmissionPdfs {
    let pdf_w = environment_radiance(e, w).pdf;
    return EmissionPdfs(pdf_w, pdf_w * environment_disk_density(e, w, x, aim) / e.area, 1.0, false, false);
}

// A point where an environment photon crosses the plane facing w (coordinates in the plane's
// basis b0, b1 about the bounding sphere's centre), and the weight its flux takes for where it
// was drawn: 1 from the disk of radius R covering the scene alone.
struct EnvironmentOrigin {
    q: vec2f,
    weight: f32,
}

// With aim.fraction = f > 0: with probability f a point on the disk of radius r covering the
// sphere about the aimed-at visible points (the box of their positions, widened by their
// largest radius), otherwise on the disk of radius R covering the scene, as without. Its
// density on the plane is the mixture's, p(q) = f 1[q in the small disk] / (pi r^2) + (1 - f)
// 1[q in the large disk] / (pi R^2), and the photon's flux, L pi R^2 / p(w) from the large disk
// alone, takes the factor 1 / (pi R^2 p(q)) (one-sample MIS over the two disks with the balance
// heuristic): unbiased, as the large disk alone reaches every point of the scene, and where
// the small disk covers the visible points its photons cost (r / R)^2 of a whole-disk
// photon's. A photon from one disk evaluates membership of the other (its own by
// construction, so that a rounding at the rim cannot drop it). u.x picks the disk and is
// stretched back to [0, 1): with f = 0 the point and the random numbers are those of the whole
// disk alone, bit for bit.
fn environment_origin(e: Emitter, b0: vec3f, b1: vec3f, u: vec2f, aim: EnvironmentAim) -> EnvironmentOrigin {
    let f = aim.fraction;
    let big = e.radius;
    let max_r = aim.max_radius;
    if !(f > 0.0) || !(max_r > 0.0) {
        return EnvironmentOrigin(big * sample_disk(u), 1.0);
    }
    let hi = aim.hi;
    let lo = aim.lo;
    let r = 0.5 * length(hi - lo) + max_r;
    if !(r < big) {
        return EnvironmentOrigin(big * sample_disk(u), 1.0);
    }
    let c = 0.5 * (lo + hi) - e.position;
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

// A photon from environment e: arriving from w, uniform on the sphere, through a point uniform
// on the disk of the bounding sphere's radius R facing w, placed outside the sphere (pbrt-v4
// sec. 12.5.3, UniformInfiniteLight::SampleLe): L / ((1 / 4 pi) (1 / pi R^2)); from an envmap,
// w by its distribution (pbrt-v4 ImageInfiniteLight::SampleLe): L(w) pi R^2 / p(w). With
// `aim`, the point is drawn from a mixture of disks (environment_origin).
fn environment_emit(e: Emitter, u_pos: vec2f, u_dir: vec2f, scale: f32, aim: EnvironmentAim) -> EmittedPhoton {
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
    return EmittedPhoton(p, -w, flux * o.weight, CAMERA_MEDIUM, vec3f(0.0));
}
