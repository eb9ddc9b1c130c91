// Path tracing, for comparison with SPPM: one sample per pixel per pass, added to `radiance`.
// Naive (frame.nee == 0): emission is found only by hitting it, so point and directional
// lights stay dark. With next-event estimation (frame.nee == 1): at diffuse and glossy
// vertices a light is sampled by power and joined by a shadow ray; area lights are weighted
// against BSDF sampling by the power heuristic (Veach 1997, sec. 9.2.4), delta lights taken
// whole. Scene, camera, lights and BSDF sampling are the ones SPPM's kernels use.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import camera
#import lights

// Per pixel: the sum of the passes' samples (rgb) and the sample count (w).
@group(0) @binding(16) var<storage, read_write> radiance: array<vec4f>;

const STREAM_PATH: u32 = 2u;

// Power heuristic with beta = 2.
fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    return a / (a + pdf_b * pdf_b);
}

// Whether nothing blocks the segment from p (already offset) along unit wi for distance t.
fn unoccluded(p: vec3f, wi: vec3f, t: f32) -> bool {
    return trace_closest(p, wi, t * (1.0 - 1e-4)).prim_ref == 0xffffffffu;
}

// Next-event estimate at surface s seen from wo: one light, chosen by power, and a point on
// it. Returns its contribution without the path throughput.
fn sample_light(s: Surface, wo: vec3f, m: Material, albedo: vec3f, rng: ptr<function, Rng>) -> vec3f {
    let e = emitters[find_emitter(rng_next(rng))];
    let u = rng_next2(rng);
    var wi: vec3f;
    var li: vec3f;
    var dist: f32;
    // Solid-angle density of this light sample; 0 marks a delta light (no MIS).
    var pdf_light = 0.0;
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        let to = e.position - s.p;
        dist = length(to);
        wi = to / dist;
        li = e.radiance / (dist * dist * e.pmf);
    } else if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        wi = -e.direction;
        dist = 3.4e38;
        li = e.radiance / e.pmf;
    } else {
        let l = sample_area_emitter(e, u);
        let to = l.p - s.p;
        dist = length(to);
        wi = to / dist;
        let cos_l = -dot(wi, l.n);
        if cos_l <= 0.0 || dist <= 0.0 {
            return vec3f(0.0);
        }
        pdf_light = area_emitter_density(l.shape) * dist * dist / cos_l;
        li = shapes[l.shape].emission / pdf_light;
    }
    // Only the side the path arrived on receives light.
    if dot(wi, s.ng) * dot(wo, s.ng) <= 0.0 {
        return vec3f(0.0);
    }
    var f = albedo * INV_PI;
    var pdf_bsdf = abs(dot(wi, s.ns)) * INV_PI;
    if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
        let g = glossy_eval(m.albedo, m.roughness, wo, wi, s.ns);
        f = g.f;
        pdf_bsdf = g.pdf;
    }
    let cos_i = abs(dot(wi, s.ns));
    if all(f == vec3f(0.0)) || !unoccluded(offset_origin(s.p, s.ng, wi), wi, dist) {
        return vec3f(0.0);
    }
    let weight = select(power_heuristic(pdf_light, pdf_bsdf), 1.0, pdf_light == 0.0);
    return f * cos_i * li * weight;
}

@compute @workgroup_size(64)
fn path_trace(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let pixel = gid.x + gid.y * groups.x * 64u;
    if pixel >= frame.width * frame.height {
        return;
    }
    // Keyed by the pixel's index in the whole image (this may be a band of it).
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_PATH, pixel + frame.row_offset * frame.width);
    let ray = camera_ray(pixel % frame.width, pixel / frame.width, &rng);
    var o = ray.o;
    var d = ray.d;
    var beta = vec3f(1.0);
    var l = vec3f(0.0);
    // Density of the BSDF sample that led here, for MIS at an emitter it hits; 0 after the
    // camera and after specular or rough-dielectric scattering, which NEE does not sample.
    var pdf_prev = 0.0;
    // A path has at most max_depth scattering events, so max_depth + 1 segments.
    for (var depth = 0u; depth <= frame.max_depth; depth++) {
        let hit = trace_closest(o, d, 3.4e38);
        if hit.prim_ref == 0xffffffffu {
            break;
        }
        let s = surface_at(hit, o, d);
        let shape = shapes[s.shape];
        if shape.emits != 0u && dot(d, s.ng) < 0.0 {
            var weight = 1.0;
            if frame.nee != 0u && pdf_prev > 0.0 {
                let pdf_light = area_emitter_density(s.shape) * hit.t * hit.t / -dot(d, s.ng);
                weight = power_heuristic(pdf_prev, pdf_light);
            }
            l += beta * shape.emission * weight;
        }
        if depth == frame.max_depth {
            break;
        }
        let m = materials[s.material];
        let wo = -d;
        if m.kind == MATERIAL_DIFFUSE {
            let albedo = diffuse_albedo(m, s.uv);
            if frame.nee != 0u {
                l += beta * sample_light(s, wo, m, albedo, &rng);
            } else {
                // The same numbers are drawn either way, so the two methods share streams.
                rng_next(&rng);
                rng_next2(&rng);
            }
            let n_in = select(-s.ns, s.ns, dot(d, s.ng) < 0.0);
            let wi = sample_cosine_hemisphere(n_in, rng_next2(&rng));
            if dot(wi, s.ng) * dot(d, s.ng) >= 0.0 {
                break;
            }
            beta *= albedo;
            pdf_prev = abs(dot(wi, s.ns)) * INV_PI;
            d = wi;
        } else {
            if USES_GLOSSY && m.kind == MATERIAL_GLOSSY && frame.nee != 0u {
                l += beta * sample_light(s, wo, m, m.albedo, &rng);
            }
            let next = sample_nondiffuse(m, d, s, vec3f(rng_next2(&rng), rng_next(&rng)), true);
            if all(next.weight == vec3f(0.0)) {
                break;
            }
            beta *= next.weight;
            pdf_prev = 0.0;
            if USES_GLOSSY && m.kind == MATERIAL_GLOSSY {
                pdf_prev = glossy_eval(m.albedo, m.roughness, wo, next.wi, s.ns).pdf;
            }
            d = next.wi;
        }
        o = offset_origin(s.p, s.ng, d);
        // Russian roulette after three bounces, keeping the largest channel's weight.
        if depth >= 3u {
            let q = max(0.05, 1.0 - max_component(beta));
            if rng_next(&rng) < q {
                break;
            }
            beta /= 1.0 - q;
        }
    }
    // A NaN or infinite sample counts as black rather than poisoning the pixel.
    let ok = all(l == l) && all(abs(l) < vec3f(3.0e38));
    radiance[pixel] += vec4f(select(vec3f(0.0), l, ok), 1.0);
}
