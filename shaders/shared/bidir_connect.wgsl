// Vertex connection (Veach 1997 sec. 10.2; SmallVCM's ConnectVertices): a camera subpath's
// vertex joined by a shadow ray to each stored vertex of its light subpath
// (shared/light_vertex.wgsl), weighted by the balance heuristic over every strategy that makes
// the same path (shared/vcm.wgsl). The bidirectional camera kernel (bidir_camera.wgsl) sets
// bidir_light_path before it traces; kernels without light vertices import
// bidir_connect_none.wgsl instead.

#import types
#import sampling
#import scene
#import bsdf
#import direct
#import vcm
#import bidir
#import light_vertex
#import grid

// The hashed grid of the pass's light vertices (vcm), built by SPPM's grid kernels.
@group(0) @binding(31) var<storage, read> grid_params: GridParams;
@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
// A bucket's light vertices in order of key (merge_order.wgsl): position and slot.
@group(0) @binding(35) var<storage, read> merge_entries: array<vec4f>;

// The light subpath the camera subpath being traced connects to.
var<private> bidir_light_path: u32;

// The sum over the light subpath's stored vertices of what each sends to surface s (material
// m, `albedo`) towards wo through one connecting segment, weighted, without the camera
// subpath's throughput; camera_length the camera subpath's segments to s. Along the segment
// from s to light vertex v (w, distance d): f_c(wo, w) |w.ns| f_l(-w, w_prev) |w.ng_l| / d^2
// times v's throughput and the shading-normal correction of its arrival (light_trace.wgsl).
// camera_merges: whether merging at s is a strategy; camera_merged: how many of the camera
// subpath's vertices merge, s and those before (vcm.wgsl's mis_weight_connection).
fn connect_light_subpath(s: Surface, m: Material, albedo: vec3f, wo: vec3f, camera: SubpathMis, camera_length: u32, camera_merges: bool,
    camera_merged: u32) -> vec3f {
    let reverse = weighs_reverse(camera);
    var sum = vec3f(0.0);
    for (var slot = light_path_first[bidir_light_path]; slot != LIGHT_VERTEX_NONE; slot = light_vertices[slot].next) {
        let v = light_vertices[slot];
        // The connected path has camera_length + v.length scattering events; the vertices come
        // in order of length.
        if camera_length + v.length > frame.max_depth {
            break;
        }
        bidir_work[WORK_CONNECTIONS] += 1u;
        let to = v.p - s.p;
        let dist2 = dot(to, to);
        if !(dist2 > 0.0) {
            continue;
        }
        let dist = sqrt(dist2);
        let w = to / dist;
        if !bsdf_joins(m, s, wo, w) {
            continue;
        }
        let sl = light_vertex_surface(v);
        let ml = material_at(sl);
        let wl = -w;
        if !bsdf_joins(ml, sl, v.w_prev, wl) {
            continue;
        }
        let bc = bsdf_eval(s, m, albedo, wo, w);
        // Light flows from w_prev towards the camera: f_l(wl, w_prev), and bl.pdf is the
        // light vertex's BSDF sampling w_prev given wl (its reverse density).
        let bl = bsdf_eval(sl, ml, ml.albedo, wl, v.w_prev);
        let correction = abs(dot(v.w_prev, sl.ns)) / max(abs(dot(v.w_prev, sl.ng)), 1e-8);
        let c = v.beta * bc.f * bl.f * (abs(dot(w, s.ns)) * correction * abs(dot(wl, sl.ng)) / dist2);
        if all(c == vec3f(0.0)) {
            continue;
        }
        let light_pdf_w = bsdf_eval(sl, ml, ml.albedo, v.w_prev, wl).pdf;
        var camera_rev_pdf_w = 0.0;
        if reverse {
            camera_rev_pdf_w = bsdf_eval(s, m, albedo, w, wo).pdf;
        }
        let camera_pdf_a = bc.pdf * abs(dot(wl, sl.ns)) / dist2;
        let light_pdf_a = light_pdf_w * abs(dot(w, s.ns)) / dist2;
        let light = SubpathMis(v.d_vcm, v.d_vc, v.d_vm, v.d_merge);
        let weight = mis_weight_connection(camera, light, camera_pdf_a, camera_rev_pdf_w, light_pdf_a, bl.pdf, camera_merges,
            camera_merged, vcm_merges_light(ml, v.length), camera_length == 1u, v.length == 1u, bidir_factors());
        if unoccluded(offset_origin(s.p, s.ng, w), offset_origin(v.p, sl.ng, wl)) {
            sum += c * weight;
        }
    }
    return sum;
}

// Vertex merging (Georgiev et al. 2012, sec. 4; SmallVCM's RangeQuery): the light vertices
// within the pass's radius r of surface point s, each the density estimate
// f(wo, w_prev) beta / (pi r^2 n_light) of the light arriving at s, weighted against the other
// strategies; without the camera subpath's throughput. Each light vertex is listed in the
// bucket of its own cell alone (grid_build.wgsl's LISTS_OWN_CELL), so every one within r of s
// lies in a cell that s's box [s.p - r, s.p + r] overlaps: the buckets of those cells are
// visited, each once (point_buckets), each listing its vertices' positions and slots in
// ascending order of key (merge_order.wgsl). Only light
// arriving on the side of the surface that wo sees merges, as SmallVCM's BSDF evaluation
// decides (a thin shell's other side does not), on the same surface or one facing it (below).
// The bias of the rest, the density estimate's over the radius, vanishes with it.
// camera_merged: how many of the camera subpath's vertices merge, s and those before (s is one
// of its first MERGES_A_PATH that merge: vcm.wgsl).
fn merge_light_vertices(s: Surface, m: Material, albedo: vec3f, wo: vec3f, camera: SubpathMis, camera_length: u32,
    camera_merged: u32) -> vec3f {
    let r = frame.global_radius;
    let buckets = point_buckets(grid_params, s.p, r);
    let reverse = weighs_reverse(camera);
    var sum = vec3f(0.0);
    for (var k = 0u; k < 8u; k++) {
        if !visits(buckets, k) {
            continue;
        }
        let h = buckets.h[k];
        for (var e = grid_cell_start[h]; e < grid_cell_start[h + 1u]; e++) {
            // Its position first: most of a bucket's vertices lie beyond the radius.
            let entry = merge_entries[e];
            bidir_work[WORK_MERGE_CANDIDATES] += 1u;
            if !within_radius(s.p, r, entry.xyz) {
                continue;
            }
            let v = light_vertices[bitcast<u32>(entry.w)];
            if camera_length + v.length > frame.max_depth + 1u {
                continue;
            }
            let wi = v.w_prev;
            if dot(wi, s.ng) * dot(wo, s.ng) <= 0.0 || one_sided_culls(m, s, wi) {
                continue;
            }
            // One surface (normals within 60 degrees), or two that face each other (a room's
            // corner: each vertex in front of the other's surface). Two faces of a block that
            // turn away from each other do not merge: the band of width r along its edge would
            // take the light of the other face (on cornell-box its lit top into the front's top
            // rows).
            let n = select(-s.ng, s.ng, dot(wo, s.ng) > 0.0);
            let n_light = select(-v.ng, v.ng, dot(wi, v.ng) > 0.0);
            let to = v.p - s.p;
            if dot(n, n_light) < 0.5 && !(dot(to, n) > 0.0 && dot(to, n_light) < 0.0) {
                continue;
            }
            let b = bsdf_eval(s, m, albedo, wo, wi);
            if all(b.f == vec3f(0.0)) {
                continue;
            }
            var rev_pdf_w = 0.0;
            if reverse {
                rev_pdf_w = bsdf_eval(s, m, albedo, wi, wo).pdf;
            }
            let weight = mis_weight_merge(camera, SubpathMis(v.d_vcm, v.d_vc, v.d_vm, v.d_merge), b.pdf, rev_pdf_w, camera_merged,
                camera_length == 1u, v.length == 1u, bidir_factors());
            sum += b.f * v.beta * weight;
        }
    }
    return sum / eta_vcm();
}
