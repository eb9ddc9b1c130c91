// The emitter dispatcher: choosing a light in proportion to power, and the one entry for each
// operation on it, calling its kind. One file a kind in shared/emitter/, each with its model
// and parameters at the top, its EMITTER_* kind and its entry points <kind>_sample (next-event
// estimation from a receiving point) and <kind>_emit (a photon leaving it): area, point,
// spot, directional and environment; shared by them: light_sample (the result types). Only
// the kinds a scene has are compiled in: each file's USES_* overrides, set by the host
// (src/scene/emitter/). sample_light and light_pdf are the light side of next-event
// estimation, for the path tracer and SPPM's camera pass alike (shared/direct.wgsl);
// emit_light starts every photon (photon_pass.wgsl).
//
// A new kind takes its own file here, its import and a branch in sample_light and emit_light,
// and its host file in src/scene/emitter/ (docs/guide/how-it-works.md, "Emitter kinds").

#import cdf
#import emitter/light_sample
#import emitter/area
#import emitter/point
#import emitter/spot
#import emitter/directional
#import emitter/environment

@group(0) @binding(15) var<storage, read> emitters: array<Emitter>;

// The environment, always the last emitter; only where USES_ENVIRONMENT.
fn environment() -> Emitter {
    return emitters[frame.emitter_count - 1u];
}

// Index of the emitter whose cdf interval holds u.
fn find_emitter(u: f32) -> u32 {
    return find_cdf(Cdf(CDF_EMITTERS, 0u, vec2u(0u), 0u), frame.emitter_count, u);
}

// Choose a light in proportion to power (u.x) and a point on it or a direction to it (u.yz),
// for the receiving point p.
fn sample_light(p: vec3f, u: vec3f) -> LightSample {
    let e = emitters[find_emitter(u.x)];
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        return point_sample(e, p, u);
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        return spot_sample(e, p, u);
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        return directional_sample(e, p, u);
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        return environment_sample(e, p, u);
    }
    return area_sample(e, p, u);
}

// Solid-angle density with which sample_light, called at p, picks a direction that meets
// emitting primitive prim_ref (of shape `shape`) at distance t, at cosine cos_l to its normal:
// the only lights a ray can hit are area lights (area_pdf).
fn light_pdf(p: vec3f, prim_ref: u32, shape: u32, t: f32, cos_l: f32) -> f32 {
    return area_pdf(p, prim_ref, shape, t, cos_l);
}

// Radiance of the environment from direction w (unit, towards it), and the solid-angle
// density with which sample_light picks w. Only where USES_ENVIRONMENT.
fn environment_eval(w: vec3f) -> EnvmapEval {
    return environment_radiance(environment(), w);
}

// A photon leaving light e (chosen by find_emitter), from u_pos and u_dir: its flux relative
// to the total power, beta = Le cos / (pmf pdf(position) pdf(direction)) / power_total; an
// environment's aimed as `aim` says.
fn emit_light(e: Emitter, u_pos: vec2f, u_dir: vec2f, aim: EnvironmentAim) -> EmittedPhoton {
    let scale = 1.0 / (e.pmf * frame.power_total);
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        return point_emit(e, u_pos, u_dir, scale);
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        return spot_emit(e, u_pos, u_dir, scale);
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        return directional_emit(e, u_pos, u_dir, scale);
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        return environment_emit(e, u_pos, u_dir, scale, aim);
    }
    return area_emit(e, u_pos, u_dir, scale);
}

// The MIS densities (EmissionPdfs) of photon ph that light e emitted (emit_light, an
// environment's with environment_light_aim), for the bidirectional methods.
fn emission_pdfs(e: Emitter, ph: EmittedPhoton) -> EmissionPdfs {
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        return point_emission_pdfs(e);
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        return spot_emission_pdfs(e, ph.d);
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        return directional_emission_pdfs(e);
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        return environment_emission_pdfs(e, -ph.d, ph.o, environment_light_aim(e));
    }
    return area_emission_pdfs(area_light_shape(e), dot(ph.d, ph.n));
}

// The shape of area emitter e's primitive.
fn area_light_shape(e: Emitter) -> u32 {
    if is_sphere_light(e.prim_ref) {
        return spheres[e.prim_ref & ~SPHERE_BIT].shape;
    }
    return triangles[e.prim_ref].shape;
}

// A light sample for next-event estimation (sample_light's, the same numbers) with what the
// bidirectional methods' MIS needs of it: pdfs.direct_pdf_a the density of the light's point
// (area measure, light choice included; its pmf for a delta light), pdfs.emission_pdf_w that
// of the light emitting towards p, pdfs.cos_light the cosine there.
struct LightSampleMis {
    ls: LightSample,
    pdfs: EmissionPdfs,
}

fn sample_light_mis(p: vec3f, u: vec3f) -> LightSampleMis {
    let e = emitters[find_emitter(u.x)];
    if USES_POINT_LIGHTS && e.kind == EMITTER_POINT {
        return LightSampleMis(point_sample(e, p, u), point_emission_pdfs(e));
    }
    if USES_SPOT_LIGHTS && e.kind == EMITTER_SPOT {
        let ls = spot_sample(e, p, u);
        return LightSampleMis(ls, spot_emission_pdfs(e, -ls.wi));
    }
    if USES_DIRECTIONAL_LIGHTS && e.kind == EMITTER_DIRECTIONAL {
        return LightSampleMis(directional_sample(e, p, u), directional_emission_pdfs(e));
    }
    if USES_ENVIRONMENT && e.kind == EMITTER_ENVIRONMENT {
        let ls = environment_sample(e, p, u);
        return LightSampleMis(ls, environment_emission_pdfs(e, ls.wi, p, environment_light_aim(e)));
    }
    let ls = area_sample(e, p, u);
    return LightSampleMis(ls, area_emission_pdfs(area_light_shape(e), ls.cos_l));
}
