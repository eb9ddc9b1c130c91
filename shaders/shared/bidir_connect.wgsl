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

// The light subpath the camera subpath being traced connects to.
var<private> bidir_light_path: u32;

// The sum over the light subpath's stored vertices of what each sends to surface s (material
// m, `albedo`) towards wo through one connecting segment, weighted, without the camera
// subpath's throughput; camera_length the camera subpath's segments to s. Along the segment
// from s to light vertex v (w, distance d): f_c(wo, w) |w.ns| f_l(-w, w_prev) |w.ng_l| / d^2
// times v's throughput and the shading-normal correction of its arrival (light_trace.wgsl).
fn connect_light_subpath(s: Surface, m: Material, albedo: vec3f, wo: vec3f, camera: SubpathMis, camera_length: u32) -> vec3f {
    let path = bidir_light_path;
    let count = light_path_length[path];
    var sum = vec3f(0.0);
    for (var k = 0u; k < count; k++) {
        let v = light_vertices[path * frame.max_depth + k];
        // The connected path has camera_length + v.length scattering events; the vertices come
        // in order of length.
        if camera_length + v.length > frame.max_depth {
            break;
        }
        let to = v.p - s.p;
        let dist2 = dot(to, to);
        if !(dist2 > 0.0) {
            continue;
        }
        let dist = sqrt(dist2);
        let w = to / dist;
        if (dot(w, s.ng) * dot(wo, s.ng) <= 0.0 && m.kind != MATERIAL_DIELECTRIC) || one_sided_culls(m, s, w) {
            continue;
        }
        let sl = light_vertex_surface(v);
        let ml = material_at(sl);
        let wl = -w;
        if (dot(wl, sl.ng) * dot(v.w_prev, sl.ng) <= 0.0 && ml.kind != MATERIAL_DIELECTRIC) || one_sided_culls(ml, sl, wl) {
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
        let camera_rev_pdf_w = bsdf_eval(s, m, albedo, w, wo).pdf;
        let camera_pdf_a = bc.pdf * abs(dot(wl, sl.ns)) / dist2;
        let light_pdf_a = light_pdf_w * abs(dot(w, s.ns)) / dist2;
        let light = SubpathMis(v.d_vcm, v.d_vc, v.d_vm);
        let weight = mis_weight_connection(camera, light, camera_pdf_a, camera_rev_pdf_w, light_pdf_a, bl.pdf, bidir_factors());
        if unoccluded(offset_origin(s.p, s.ng, w), offset_origin(v.p, sl.ng, wl)) {
            sum += c * weight;
        }
    }
    return sum;
}
