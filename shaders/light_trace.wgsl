// Light tracing (`--method lt`; Veach 1997 sec. 10.2, Arvo & Kirk's particle tracing): light
// subpaths leave the emitters as SPPM's photons do (emit_light, shared/lights.wgsl) and scatter as they do;
// every vertex whose BSDF can be evaluated, and the point an area light emits from, is joined
// to the camera (a point of its lens) by a shadow ray, and what it sends the camera is splatted into the pixels
// around where it lands (camera_importance.wgsl, splat.wgsl). frame.photon_count subpaths a
// pass, each splat divided by their number: the pass's splats sum to one estimate of the
// image, which splat_accumulate adds to the per-pixel sums the path tracers keep.
//
// A subpath's throughput beta estimates flux arriving on surfaces (photon_pass's, times the
// total power). At a vertex x reached along d, light L(x -> camera) = f(wo, -d) |d.ns| Li is
// estimated by beta f |d.ns| / |d.ng| (the flux's density is per unit area on the geometric
// normal; the ratio is pbrt-v4's shading-normal correction for light carrying importance),
// and the pixel measures g L cos_x / (dist^2 cos^3 theta A_pix).

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import lights
#import medium
#import direct
#import camera
#import splat
#import camera_importance
#import vcm
#import bidir
#import light_vertex

const STREAM_LIGHT: u32 = 3u;

// Bidirectional path tracing's light pass (method bpt, set by src/integrators/light.rs): each
// subpath also keeps its MIS quantities (shared/vcm.wgsl) and stores its vertices for the
// camera subpaths' connections (shared/light_vertex.wgsl), its joins to the camera are
// weighted against the other strategies, and a light's own point is left to camera paths
// that see it.
override BIDIR: bool = false;

// Join the point p (on surface s, when `on_surface`) to the camera and splat what it sends
// there: `le` the light leaving p towards the camera per unit of importance (radiance times
// cos_x, already divided by the pass's subpath count).
fn connect_to_camera(p_offset: vec3f, view: CameraView, c: vec3f) {
    if view.importance <= 0.0 || all(c == vec3f(0.0)) {
        return;
    }
    // What a fixed-point splat holds: a point grazing the lens plane would otherwise send an
    // overflowing or infinite value.
    let value = c * view.importance;
    if !(all(value >= vec3f(0.0)) && all(value < vec3f(1.0e9))) {
        return;
    }
    if !unoccluded(p_offset, view.lens) {
        return;
    }
    splat_filtered(view.raster, value);
}

@compute @workgroup_size(64)
fn light_trace(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    // This dispatch's part of the pass: subpaths [work_first, work_end).
    let index = frame.work_first + gid.x + gid.y * groups.x * 64u;
    if index >= min(frame.work_end, frame.photon_count) {
        return;
    }
    var rng = rng_new(frame.seed, frame.pass_index, STREAM_LIGHT, index);
    let per_seed = max(0xffffffffu / max(frame.photon_count, 1u), 1u);
    rng_sobol(&rng, (frame.pass_index % per_seed) * frame.photon_count + index, sobol_seed(frame.seed, STREAM_LIGHT, frame.pass_index / per_seed));
    // A light chosen by power and a photon leaving it, as photon_pass draws them; its flux is
    // relative to the total power, here per subpath of the pass.
    let e = emitters[find_emitter(rng_next(&rng))];
    let u_pos = rng_next2(&rng);
    let u_dir = rng_next2(&rng);
    // An environment's aimed at what the camera sees (emitter/environment.wgsl).
    let ph = emit_light(e, u_pos, u_dir, environment_light_aim(e));
    let scale = frame.power_total / f32(frame.photon_count);
    var beta = ph.beta * scale;
    var lm = SubpathMis(0.0, 0.0, 0.0, vec2f(0.0));
    // Vertices kept, and the slot of the last.
    var stored = 0u;
    var last = LIGHT_VERTEX_NONE;
    var finite_light = true;
    if BIDIR {
        light_path_first[index] = LIGHT_VERTEX_NONE;
        let pdfs = emission_pdfs(e, ph);
        lm = mis_light_start(pdfs.direct_pdf_a, pdfs.emission_pdf_w, pdfs.cos_light, pdfs.delta, bidir_factors());
        finite_light = pdfs.finite;
    }
    // The point an area light emits from, seen by the camera: Le cos_x / (pmf pdf_pos), which
    // is beta / pi (area_emit draws the direction by cosine), from the light's front.
    if !BIDIR && any(ph.n != vec3f(0.0)) {
        var u_lens = vec2f(0.0);
        if frame.lens_radius > 0.0 {
            u_lens = rng_next2(&rng);
        }
        let view = camera_view(ph.o, lens_point(u_lens));
        let cos_x = dot(view.wi, ph.n);
        if cos_x > 0.0 {
            connect_to_camera(ph.o, view, beta * (cos_x * INV_PI));
        }
    }
    var o = ph.o;
    var d = ph.d;
    var depth = 0u;
    loop {
        if depth >= frame.max_depth {
            break;
        }
        let hit = trace_closest(o, d, 3.4e38);
        if hit.prim_ref == 0xffffffffu {
            break;
        }
        let s = surface_at(hit, o, d);
        let m = material_at(s);
        if seen_from_behind(m, s, d) {
            break;
        }
        bidir_work[WORK_LIGHT_VERTICES] += 1u;
        let finite = all(beta >= vec3f(0.0)) && all(beta < vec3f(1.0e30));
        if !finite {
            break;
        }
        // Whether merging at this vertex is a strategy (vcm), for the grid and the weights.
        let merges = vcm_merges_light(m, depth + 1u);
        if BIDIR {
            lm = mis_hit(lm, hit.t, dot(d, s.ns), depth > 0u || finite_light);
            // Kept for the camera subpaths' connections, its throughput for one subpath.
            if bsdf_samples_lights(m) {
                let slot = atomicAdd(&light_vertex_count[0], 1u);
                if slot < arrayLength(&light_vertices) {
                    light_vertices[slot] = LightVertex(s.p, s.material, s.ng, s.shape, s.ns, depth + 1u, -d, lm.d_vcm,
                        beta * f32(frame.photon_count), lm.d_vc, s.uv, lm.d_vm, LIGHT_VERTEX_NONE, lm.d_merge);
                    if last == LIGHT_VERTEX_NONE {
                        light_path_first[index] = slot;
                    } else {
                        light_vertices[last].next = slot;
                    }
                    last = slot;
                    if merges {
                        let key = bitcast<f32>(light_vertex_key(index, stored));
                        visible_points[atomicAdd(&merge_count[0], 1u)] = VisiblePoint(s.p, frame.global_radius, vec3f(key, 0.0, 0.0), slot);
                    }
                    stored += 1u;
                } else {
                    // The store is full: the host sized it from a probe (light.rs) and says
                    // how many were not kept.
                    atomicAdd(&light_vertex_count[1], 1u);
                }
            }
        }
        // Join this vertex to the camera: wo towards the camera, the light arriving along d.
        // With a thin lens, a lens point for each vertex (two numbers, drawn only then).
        if bsdf_samples_lights(m) {
            var u_lens = vec2f(0.0);
            if frame.lens_radius > 0.0 {
                u_lens = rng_next2(&rng);
            }
            let view = camera_view(s.p, lens_point(u_lens));
            let wo = view.wi;
            let wi = -d;
            if view.importance > 0.0 && bsdf_joins(m, s, wi, wo) {
                let b = bsdf_eval(s, m, m.albedo, wo, wi);
                let correction = abs(dot(wi, s.ns)) / max(abs(dot(wi, s.ng)), 1e-8);
                var c = beta * b.f * (correction * abs(dot(wo, s.ng)));
                if BIDIR {
                    // The camera's density of this vertex: its direction's, per pixel area
                    // (bidir.wgsl's camera_pdf_w), in area measure here.
                    let camera_pdf_a = view.importance * abs(dot(wo, s.ns));
                    c *= mis_weight_to_camera(lm, camera_pdf_a, b.pdf, f32(frame.photon_count), merges, depth == 0u,
                        bidir_factors()) * kept(STRATEGY_LIGHT_TRACE);
                }
                connect_to_camera(offset_origin(s.p, s.ng, wo), view, c);
            }
        }
        // Scatter as photons do (photon_pass.wgsl): a diffuse bounce draws two numbers, any
        // other three.
        var u = vec3f(rng_next2(&rng), 0.0);
        if m.kind != MATERIAL_DIFFUSE {
            u.z = rng_next(&rng);
        }
        let next = bsdf_sample(s, m, m.albedo, d, u, false, BIDIR);
        if all(next.weight == vec3f(0.0)) {
            break;
        }
        if BIDIR {
            // A delta lobe (mirror, smooth glass, a smooth plastic's coating) has no density.
            let specular = !bsdf_samples_lights(m) || next.pdf <= 0.0;
            var pdf_rev = 0.0;
            if !specular {
                pdf_rev = bsdf_eval(s, m, m.albedo, next.wi, -d).pdf;
            }
            lm = mis_scatter(lm, next.pdf, pdf_rev, abs(dot(next.wi, s.ns)), specular, merges, depth == 0u, bidir_factors());
        }
        // Russian roulette that keeps the subpath's largest channel constant.
        let beta_new = beta * next.weight;
        let q = max(0.0, 1.0 - max_component(beta_new) / max_component(beta));
        if rng_next(&rng) < q {
            break;
        }
        beta = beta_new / (1.0 - q);
        o = offset_origin(s.p, s.ng, next.wi);
        d = next.wi;
        if !(USES_MEDIA && is_null(m)) {
            depth += 1u;
        }
    }
    if BIDIR {
        bidir_count_work();
    }
}
