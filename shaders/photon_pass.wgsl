// SPPM photon pass (Hachisuka & Jensen 2009, sec. 4): photons leave the emitters, chosen in
// proportion to power, and at every diffuse hit add their flux to the visible points within
// radius; at the first hit only when the camera pass does not sample direct light. A hit is
// stored in its grid bucket's list (photon_hits), and photon_gather adds it to the points
// around it after the pass: each point then sums its photons in registers, with no atomics,
// from hits that its neighbours read too. A thread whose hit finds no room (past
// frame.hit_capacity) saves its state and stops; after the gather, the grid of visible points
// is built and the kernel runs again with frame.resume = 1 to finish those threads, depositing
// at once through the grid. Either way flux is accumulated in 32.32 fixed point
// (shared/flux.wgsl), so the sums do not depend on the order in which photons arrive or on
// where they were added: the same seed gives the same image. A point's weight (throughput
// times albedo / pi) is the same for every photon of the pass, so it multiplies the sum once,
// in update_stats, rather than each photon here.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import lights
#import lanes
#import grid
#import gather
#import flux
#import medium

@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;
// The grid's parameters, then camera_pass's words on the visible points (their largest
// radius and, with frame.env_aim > 0, their bounds as order keys: largest x, y, z in
// bounds_a.yzw, the complements of the smallest in bounds_b.xyz), copied after the grid's
// set-up.
struct PhotonGrid {
    params: GridParams,
    bounds_a: vec4u,
    bounds_b: vec4u,
}
@group(0) @binding(11) var<uniform> grid: PhotonGrid;
@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read> grid_entries: array<u32>;
// PhotonHit (shared/types.wgsl) as three vec4u, one store each.
@group(0) @binding(23) var<storage, read_write> photon_hits: array<vec4u>;
// Word 0: hits stored since the last gather (past the capacity: attempts that found no
// room). Word 1: threads that stopped for want of room. Word 2 + h: the first hit of bucket
// h's list (index plus one; 0 for none).
@group(0) @binding(24) var<storage, read_write> photon_hit_lists: array<atomic<u32>>;
// The state of each thread that stopped, as four vec4u (see suspend).
@group(0) @binding(25) var<storage, read_write> photon_suspended: array<vec4u>;

const STREAM_PHOTON: u32 = 1u;

// Add the photon's flux to visible point v if the point accepts it (shared/gather.wgsl):
// `normal` is encode_normal's, of the surface the photon hit, turned to the side it arrived
// from (volume_normal's in a medium).
fn deposit_at(v: u32, p: vec3f, d: vec3f, beta: vec3f, depth: u32, normal: u32) {
    let q = visible_points[v];
    if accepts(gatherer(q), p, d, depth, normal, frame.max_depth) {
        accumulate_flux(v, beta);
        if ADAPTIVE_RADIUS {
            accumulate_moments(v, offset_moments((p - q.p) / q.radius));
        }
    }
}

// Put a hit in bucket h's list for photon_gather; false when the pass's hits are full.
fn store_hit(h: u32, p: vec3f, d: vec3f, beta: vec3f, depth: u32, normal: u32) -> bool {
    // Looked at first, so that the count stops near the capacity and cannot wrap.
    if atomicLoad(&photon_hit_lists[0]) >= frame.hit_capacity {
        return false;
    }
    let i = atomicAdd(&photon_hit_lists[0], 1u);
    if i >= frame.hit_capacity {
        return false;
    }
    let next = atomicExchange(&photon_hit_lists[2u + h], i + 1u);
    photon_hits[3u * i] = vec4u(bitcast<vec3u>(p), next);
    photon_hits[3u * i + 1u] = vec4u(bitcast<vec3u>(d), depth);
    photon_hits[3u * i + 2u] = vec4u(bitcast<vec3u>(beta), normal);
    return true;
}

// Deposit the photons of the lanes where `deposits`: stored for photon_gather, or with
// frame.at_once, added to the visible points around them at once. False where a hit found no room
// (the thread then stops). The lanes of a SIMD group share the direct deposits
// (shared/lanes.wgsl): one photon's bucket at a time, each lane taking every n-th entry, so
// that no lane idles while another walks a long bucket. Flux is added in fixed point, so who
// adds what does not change the sums.
fn deposit(deposits: bool, p: vec3f, d: vec3f, beta: vec3f, depth: u32, normal: u32) -> bool {
    var range = vec2u(0u);
    var stored = true;
    if deposits {
        // The cell's bucket in the spatial hash of the grid (shared/grid.wgsl,
        // src/accel/grid.rs).
        let h = bucket_of(grid.params, p);
        if h != NO_BUCKET {
            if frame.at_once == 0u {
                stored = store_hit(h, p, d, beta, depth, normal);
            } else {
                range = vec2u(grid_cell_start[h], grid_cell_start[h + 1u]);
            }
        }
    }
    let rank = lane_rank();
    let lanes = lane_count();
    let ballot = lane_ballot(range.y > range.x);
    for (var word = 0u; word < 4u; word++) {
        var todo = ballot[word];
        while todo != 0u {
            let lane = 32u * word + firstTrailingBit(todo);
            todo &= todo - 1u;
            let r = lane_shuffle_u2(range, lane);
            let p_lane = lane_shuffle_f3(p, lane);
            let d_lane = lane_shuffle_f3(d, lane);
            let beta_lane = lane_shuffle_f3(beta, lane);
            let depth_lane = lane_shuffle_u(depth, lane);
            let normal_lane = lane_shuffle_u(normal, lane);
            for (var i = r.x + rank; i < r.y; i += lanes) {
                deposit_at(grid_entries[i], p_lane, d_lane, beta_lane, depth_lane, normal_lane);
            }
        }
    }
    return stored;
}

// Photons each thread traces, one after another.
const PHOTONS_PER_THREAD: u32 = 16u;

struct Photon {
    o: vec3f,
    d: vec3f,
    beta: vec3f,
    depth: u32,
    // The medium it travels through (shared/medium.wgsl).
    medium: u32,
}

// Choose a light in proportion to power and a photon leaving it (emit_light, shared/lights.wgsl),
// an environment's aimed at this pass's visible points where frame.env_aim says.
fn emit_photon(rng: ptr<function, Rng>) -> Photon {
    let e = emitters[find_emitter(rng_next(rng))];
    let u_pos = rng_next2(rng);
    let u_dir = rng_next2(rng);
    var aim = EnvironmentAim(0.0, 0.0, vec3f(0.0), vec3f(0.0));
    if USES_ENVIRONMENT {
        aim = environment_aim();
    }
    let p = emit_light(e, u_pos, u_dir, aim);
    return Photon(p.o, p.d, p.beta, 0u, p.medium);
}

// The visible points an environment's photons are aimed at: frame.env_aim of them, at the
// box of the points' positions widened by their largest radius, from camera_pass's words
// after the grid's (see `grid`).
fn environment_aim() -> EnvironmentAim {
    let hi = vec3f(from_order_key(grid.bounds_a.y), from_order_key(grid.bounds_a.z), from_order_key(grid.bounds_a.w));
    let lo = vec3f(from_order_key(~grid.bounds_b.x), from_order_key(~grid.bounds_b.y), from_order_key(~grid.bounds_b.z));
    return EnvironmentAim(frame.env_aim, bitcast<f32>(grid.bounds_a.x), lo, hi);
}

// What became of a photon after a bounce.
const PHOTON_ENDED: u32 = 0u;
const PHOTON_GOES_ON: u32 = 1u;
// Its hit found no room: the bounce is to be done again, from the same state, when resuming.
const PHOTON_NO_ROOM: u32 = 2u;

// One bounce of a photon: deposit at a diffuse hit, then scatter.
fn photon_bounce(ph: ptr<function, Photon>, rng: ptr<function, Rng>) -> u32 {
    let hit = trace_closest((*ph).o, (*ph).d, 3.4e38);
    // The state to resume from when a deposit finds no room: in a medium, the bounce has
    // drawn numbers and attenuated the flux by then, and is done again from the start.
    let ph_start = *ph;
    let rng_start = *rng;
    if USES_MEDIA && (*ph).medium != NO_MEDIUM {
        let c = medium_coefficients((*ph).medium);
        let flight = sample_flight(c, hit.t, rng_next2(rng));
        if flight.scattered {
            let p = (*ph).o + flight.t * (*ph).d;
            // The track-length estimate of the fluence: Tr / p(t) of the flux, at an isotropic
            // medium's scattering events (the phase function is the camera's, 1 / 4 pi);
            // straight from a light, where the camera pass samples direct light, none.
            let deposited = (*ph).beta * flight.weight;
            let finite = all(deposited >= vec3f(0.0)) && all(deposited < vec3f(1.0e9));
            let deposits = c.g == 0.0 && (frame.direct == 0u || (*ph).depth > 0u) && finite;
            if !deposit(deposits, p, (*ph).d, deposited, (*ph).depth, volume_normal(0u)) {
                *rng = rng_start;
                *ph = ph_start;
                return PHOTON_NO_ROOM;
            }
            // Russian roulette on the scattered flux, as at a surface.
            let beta_new = deposited * c.sigma_s;
            let q = max(0.0, 1.0 - max_component(beta_new) / max_component((*ph).beta));
            if rng_next(rng) < q {
                return PHOTON_ENDED;
            }
            (*ph).beta = beta_new / (1.0 - q);
            (*ph).o = p;
            (*ph).d = sample_phase((*ph).d, c.g, rng_next2(rng));
            (*ph).depth += 1u;
            return select(PHOTON_ENDED, PHOTON_GOES_ON, (*ph).depth < frame.max_depth);
        }
        (*ph).beta *= flight.weight;
    }
    if hit.prim_ref == 0xffffffffu {
        return PHOTON_ENDED;
    }
    let d = (*ph).d;
    let s = surface_at(hit, (*ph).o, d);
    let m = material_at(s);
    // At a diffuse hit; where the camera pass samples direct light, photons straight from a
    // light would count it twice: they deposit only after their first bounce. Called by
    // every lane that hit something, so that they all help. A photon whose flux is NaN or
    // overflows adds nothing rather than everything.
    let beta = (*ph).beta;
    let finite = all(beta >= vec3f(0.0)) && all(beta < vec3f(1.0e9));
    // A one-sided surface hit from behind scatters nothing: no deposit, and the photon ends.
    let behind = seen_from_behind(m, s, d);
    // Nothing has been drawn or changed yet in this bounce (but in a medium, undone below), so
    // when the hit finds no room the photon's state is the one to resume from.
    // On a plastic's base, with the part of its term that depends on the photon's direction.
    let deposited = bsdf_deposit(m, s, d, beta);
    let receives = bsdf_receives_photons(m);
    // The surface's side the photon arrived on, as a visible point's normal is stored: only
    // points on the same side of their own surface gather it (same_side in shared/grid.wgsl).
    let normal = encode_normal(select(-s.ng, s.ng, dot(d, s.ng) < 0.0), 0u);
    if !deposit(receives && (frame.direct == 0u || (*ph).depth > 0u) && finite && !behind, s.p, d, deposited, (*ph).depth, normal) {
        if USES_MEDIA {
            *rng = rng_start;
            *ph = ph_start;
        }
        return PHOTON_NO_ROOM;
    }
    if behind {
        return PHOTON_ENDED;
    }
    // Scatter as camera paths do (shared/bsdf.wgsl), carrying flux. A diffuse bounce draws two
    // numbers, any other three.
    var u = vec3f(rng_next2(rng), 0.0);
    if m.kind != MATERIAL_DIFFUSE {
        u.z = rng_next(rng);
    }
    let next = bsdf_sample(s, m, m.albedo, d, u, false, false);
    let wi = next.wi;
    let f = next.weight;
    if all(f == vec3f(0.0)) {
        return PHOTON_ENDED;
    }
    // Russian roulette that keeps the photon's largest channel constant (pbrt-v4 sec. 16.3).
    let beta_new = (*ph).beta * f;
    let q = max(0.0, 1.0 - max_component(beta_new) / max_component((*ph).beta));
    if rng_next(rng) < q {
        return PHOTON_ENDED;
    }
    (*ph).beta = beta_new / (1.0 - q);
    (*ph).o = offset_origin(s.p, s.ng, wi);
    (*ph).medium = medium_after((*ph).medium, s, d, wi);
    (*ph).d = wi;
    // A null boundary of a medium is no scattering event: the light a photon carries past one
    // is still direct, which the camera pass's next-event estimation reaches through it
    // (shadow_transmittance in shared/direct.wgsl).
    if !(USES_MEDIA && is_null(m)) {
        (*ph).depth += 1u;
    }
    return select(PHOTON_ENDED, PHOTON_GOES_ON, (*ph).depth < frame.max_depth);
}

// Save the state of a thread whose photon found no room, to be resumed after the gather: one
// slot per thread at most, as a thread stops at its first such hit.
fn suspend(ph: Photon, rng: Rng, next: u32, end: u32) {
    let slot = atomicAdd(&photon_hit_lists[1], 1u);
    // With media, the depth in the low 16 bits and the medium in the high 16.
    let depth = select(ph.depth, (ph.depth & 0xffffu) | (ph.medium << 16u), USES_MEDIA);
    photon_suspended[4u * slot] = vec4u(bitcast<vec3u>(ph.o), depth);
    photon_suspended[4u * slot + 1u] = vec4u(bitcast<vec3u>(ph.d), rng.state);
    photon_suspended[4u * slot + 2u] = vec4u(bitcast<vec3u>(ph.beta), next);
    photon_suspended[4u * slot + 3u] = vec4u(end, rng.index, rng.seed, rng.dim);
}

// Each thread traces PHOTONS_PER_THREAD photons and starts the next as soon as one ends, so
// the lanes of a SIMD group stay busy although path lengths differ (path regeneration,
// Novak et al. 2010). Photon i draws from its own random stream: the result does not depend
// on which thread traced it, nor on whether it stopped for want of room and was resumed.
@compute @workgroup_size(64)
fn photon_pass(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let thread = gid.x + gid.y * groups.x * 64u;
    var next: u32;
    var end: u32;
    var alive = false;
    var ph: Photon;
    var rng: Rng;
    if frame.resume == 0u {
        // This dispatch's part of the pass: photons [work_first, work_end).
        next = frame.work_first + thread * PHOTONS_PER_THREAD;
        end = min(next + PHOTONS_PER_THREAD, min(frame.work_end, frame.photon_count));
    } else {
        // Thread `thread` of those that stopped, from the state it saved.
        if thread >= atomicLoad(&photon_hit_lists[1]) {
            return;
        }
        let a = photon_suspended[4u * thread];
        let b = photon_suspended[4u * thread + 1u];
        let c = photon_suspended[4u * thread + 2u];
        let depth = select(a.w, a.w & 0xffffu, USES_MEDIA);
        ph = Photon(bitcast<vec3f>(a.xyz), bitcast<vec3f>(b.xyz), bitcast<vec3f>(c.xyz), depth, select(NO_MEDIUM, a.w >> 16u, USES_MEDIA));
        let e = photon_suspended[4u * thread + 3u];
        rng = Rng(b.w, e.y, e.z, e.w);
        next = c.w;
        end = e.x;
        alive = true;
    }
    loop {
        if !alive {
            if next >= end {
                break;
            }
            rng = rng_new(frame.seed, frame.pass_index, STREAM_PHOTON, next);
            // With the Sobol sampler: photons are numbered across passes, runs of `per_seed`
            // passes sharing one sequence (its index stays below 2^32).
            let per_seed = max(0xffffffffu / max(frame.photon_count, 1u), 1u);
            let key = frame.pass_index / per_seed;
            rng_sobol(&rng, (frame.pass_index % per_seed) * frame.photon_count + next, sobol_seed(frame.seed, STREAM_PHOTON, key));
            ph = emit_photon(&rng);
            next += 1u;
        }
        let after = photon_bounce(&ph, &rng);
        if after == PHOTON_NO_ROOM {
            suspend(ph, rng, next, end);
            break;
        }
        alive = after == PHOTON_GOES_ON;
    }
}
