// The camera side of the bidirectional methods (bpt) that needs no light vertex: the camera
// subpath's start, next-event estimation and emission hit weighted by the balance heuristic
// over every strategy of the family (shared/vcm.wgsl), where pt-nee weighs only NEE against
// BSDF sampling (shared/direct.wgsl). shared/camera_path.wgsl calls them under
// CAMERA_PATH_BIDIR; the connections to light vertices are bidir_connect.wgsl's.

#import types
#import rng
#import sampling
#import scene
#import bsdf
#import lights
#import direct
#import vcm
#import camera_importance

// vcm (src/integrators/light.rs sets it): camera subpaths also merge with the light vertices
// within the pass's radius frame.global_radius (Georgiev et al. 2012; Hachisuka et al. 2012).
override VCM_MERGE: bool = false;

// The shares of camera vertices that connect to light vertices and that merge, frame.
// connect_share and frame.merge_share (src/integrators/light.rs sets them; 1: every one), are
// drawn per 64-pixel block, depth and pass so that a workgroup's lanes agree; a join taken is
// divided by its share, and the share is the strategy's count in the heuristic (MisFactors).

// vcm's pilot counts what a pass does where frame.count_work is 1: each kernel adds its
// invocation's counts (bidir_work, indexed by WORK_*) to work_counts once, at its end
// (bidir_count_work). Words as src/layout/records.rs's.
const WORK_COUNTS: u32 = 4u;
const WORK_CAMERA_VERTICES: u32 = 0u;
const WORK_CONNECTIONS: u32 = 1u;
const WORK_MERGE_CANDIDATES: u32 = 2u;
const WORK_LIGHT_VERTICES: u32 = 3u;
@group(0) @binding(34) var<storage, read_write> work_counts: array<atomic<u32>, WORK_COUNTS>;
var<private> bidir_work: array<u32, WORK_COUNTS>;

// Adds this invocation's counts to work_counts (where frame.count_work asks for them).
fn bidir_count_work() {
    if frame.count_work == 0u {
        return;
    }
    for (var k = 0u; k < WORK_COUNTS; k++) {
        if bidir_work[k] != 0u {
            atomicAdd(&work_counts[k], bidir_work[k]);
        }
    }
}

// The 64-pixel block of the camera subpath being traced (bidir_camera.wgsl sets it).
var<private> bidir_block: u32;

// Whether the camera vertex at `depth` takes the join of the given share (0: connect, 1:
// merge), drawn for the block.
fn bidir_takes(share: f32, which: u32, depth: u32) -> bool {
    if share >= 1.0 {
        return true;
    }
    if share <= 0.0 {
        return false;
    }
    let h = pcg_hash(frame.seed ^ pcg_hash(frame.pass_index ^ pcg_hash(bidir_block ^ pcg_hash(depth * 2u + which))));
    return f32(h >> 8u) * (1.0 / 16777216.0) < share;
}

// The strategies whose weighted contributions a pass keeps (frame.strategies: all but for
// `--strategy-images`): each is still weighed against every strategy of the method, so that
// the images of the strategies add up to the method's image. Bits as src/layout/records.rs's.
const STRATEGY_EMISSION: u32 = 1u;
const STRATEGY_NEE: u32 = 2u;
const STRATEGY_CONNECT: u32 = 4u;
const STRATEGY_MERGE: u32 = 8u;
const STRATEGY_LIGHT_TRACE: u32 = 16u;

// Whether vcm merges at a vertex of material m, decided from the material alone so that the
// light and the camera subpath agree: where the BSDF is diffuse (a Lambertian surface, a
// plastic whose smooth coating is a delta lobe and leaves the diffuse base to evaluate), as
// SPPM gathers only at diffuse lobes. On a glossy lobe the density estimate would blur the
// reflection over the radius (a bias that is light paths' own: connections and light tracing
// carry it); mis_scatter and the weights leave merging out of the MIS there.
fn vcm_merges_at(m: Material) -> bool {
    return VCM_MERGE && frame.merge_share > 0.0 && (m.kind == MATERIAL_DIFFUSE || (is_plastic(m) && !rough_coat(m)));
}

// Whether a light vertex of material m, `length` scattering events from its light (1: reached
// straight from it), merges: where its material merges, but not straight from the light. The
// light there is next-event estimation's and BSDF sampling's to find, without a density
// estimate's noise and blur, as SPPM's photons deposit only after a bounce when its camera pass
// samples direct light (photon_pass.wgsl). Merging a light vertex of length 1 is then no
// strategy of any path: next-event estimation's weight and emission's leave it out on the
// camera's side too (vcm.wgsl).
fn vcm_merges_light(m: Material, length: u32) -> bool {
    return vcm_merges_at(m) && length > 1u;
}

// 1 where `strategy` is kept, else 0.
fn kept(strategy: u32) -> f32 {
    return select(0.0, 1.0, (frame.strategies & strategy) != 0u);
}

// eta_vcm = pi r^2 n_light: merging's density relative to a connection's (shared/vcm.wgsl).
fn eta_vcm() -> f32 {
    return PI * frame.global_radius * frame.global_radius * f32(frame.photon_count);
}

// The strategies weighed: bpt's connections only (vm 0; vc then only scales dVM, unused), or
// vcm's connections and merging, each at its share (at a merge share of 0, connections only).
fn bidir_factors() -> MisFactors {
    if VCM_MERGE && frame.merge_share > 0.0 {
        let eta = eta_vcm() * frame.merge_share;
        return MisFactors(mis(1.0 / eta), mis(eta), mis(frame.connect_share));
    }
    return MisFactors(0.0, 0.0, mis(frame.connect_share));
}

// Solid-angle density, per unit of pixel area, with which the camera sends a ray along unit d
// through its pixel: the image plane at distance 1 along the view axis, pixels of area
// a_pix there, so 1 / (a_pix cos^3 theta) (camera_importance.wgsl's camera_view, whose
// importance times cos_x is the same density in area measure at the point seen).
fn camera_pdf_w(d: vec3f) -> f32 {
    let cos_theta = max(dot(d, view_axis()), 1e-8);
    return 1.0 / (pixel_area() * cos_theta * cos_theta * cos_theta);
}

// The camera subpath's MIS quantities as it leaves the camera along d, n_light light subpaths
// a pass (frame.photon_count).
fn bidir_camera_start(d: vec3f) -> SubpathMis {
    return mis_camera_start(camera_pdf_w(d), f32(frame.photon_count));
}

// Weight of the emission a camera subpath (its quantities `camera`, updated at the hit) finds
// on area light shape `shape` at cosine cos_l; seen straight from the camera, 1 (light tracing
// does not join a light's own point to the camera in bpt). last_merges: whether the subpath's
// vertex before the light merges (vcm.wgsl's mis_weight_emission).
fn bidir_emission_weight(camera: SubpathMis, shape: u32, cos_l: f32, first_segment: bool, last_merges: bool) -> f32 {
    if first_segment {
        return 1.0;
    }
    let pdfs = area_emission_pdfs(shape, cos_l);
    return mis_weight_emission(camera, pdfs.direct_pdf_a, pdfs.emission_pdf_w, last_merges, bidir_factors());
}

// Weight of the environment a camera subpath (its quantities `camera`, as its last vertex
// left them: a light at infinity's densities are not in area measure, so no mis_hit) finds
// along d from o, escaping; seen straight from the camera, 1 (no other strategy makes that
// path). last_merges as for bidir_emission_weight.
fn bidir_escaped_weight(camera: SubpathMis, o: vec3f, d: vec3f, first_segment: bool, last_merges: bool) -> f32 {
    if first_segment {
        return 1.0;
    }
    let e = environment();
    let pdfs = environment_emission_pdfs(e, d, o, environment_light_aim(e));
    return mis_weight_emission(camera, pdfs.direct_pdf_a, pdfs.emission_pdf_w, last_merges, bidir_factors());
}

// Next-event estimate at surface s seen from wo (direct_light's, the same numbers and
// visibility), weighted against every other strategy that makes the same path; `first`
// whether s is the camera subpath's first vertex.
fn bidir_direct_light(s: Surface, wo: vec3f, m: Material, albedo: vec3f, camera: SubpathMis, first: bool, u: vec3f) -> vec3f {
    let sample = sample_light_mis(s.p, u);
    let ls = sample.ls;
    if all(ls.li == vec3f(0.0)) || !bsdf_joins(m, s, wo, ls.wi) {
        return vec3f(0.0);
    }
    let b = bsdf_eval(s, m, albedo, wo, ls.wi);
    if all(b.f == vec3f(0.0)) || !unoccluded(offset_origin(s.p, s.ng, ls.wi), ls.p_light) {
        return vec3f(0.0);
    }
    let p = sample.pdfs;
    // The light point's density in solid angle from s, by area (a sphere's too: see
    // area_emission_pdfs), and for a delta light its pmf times dist^2; a light at infinity's
    // is its pmf (SmallVCM's directional light).
    var direct_pdf_w = p.direct_pdf_a;
    if p.finite {
        direct_pdf_w *= ls.dist * ls.dist / max(p.cos_light, 1e-8);
    }
    var rev_pdf_w = 0.0;
    if weighs_reverse(camera) {
        rev_pdf_w = bsdf_eval(s, m, albedo, ls.wi, wo).pdf;
    }
    let cos_to_light = dot(ls.wi, s.ns);
    let weight = mis_weight_nee(camera, direct_pdf_w, p.emission_pdf_w, cos_to_light, p.cos_light, b.pdf, rev_pdf_w, p.delta,
        first, bidir_factors());
    return b.f * abs(cos_to_light) * ls.li * weight;
}
