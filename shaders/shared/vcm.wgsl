// Multiple importance sampling over the strategies of the bidirectional family (vertex
// connection and merging: Georgiev, Krivanek, Davidovic & Slusallek 2012; the recursive form
// of Georgiev's "Implementing vertex connection and merging", 2012, whose quantities SmallVCM
// names dVCM, dVC and dVM). A path of k segments can be made by every split of it into a
// light subpath of s vertices and a camera subpath: emission hit by the camera path (s = 0),
// next-event estimation (s = 1), a connection between the subpaths' ends (1 < s < k), light
// tracing (the light subpath joined to the camera), and merging a light vertex with a camera
// vertex within the radius. Each strategy's weight is its density over the sum of all the
// strategies' densities (the balance heuristic; vcm takes their squares, the power heuristic:
// `mis` below); the recursive quantities carry, along each
// subpath, the sums over the strategies that split it on that side, so that a weight costs
// a few multiplications at the vertex where the strategy is evaluated.
//
// Densities: *PdfW in solid angle, *PdfA in area; `fwd` the density of the direction the
// subpath was extended in, `rev` of the opposite one (the other subpath sampling it). eta_vcm =
// pi r^2 n_light (n_light light subpaths a pass): merging's density relative to connection's.

// The heuristic's power of a density: the balance heuristic (Veach 1997 eq. 9.10, power 1)
// for bpt, the power heuristic with exponent 2 (eq. 9.13) for vcm (src/integrators/light.rs
// sets it), where it lowered the error at equal passes by 8-21% on the canonical scenes and
// veach-bidir and left bpt's within 6% either way (BENCHMARKS.md "VCM"). Every density and
// count of the recursion and the weights goes through it.
override MIS_POWER: bool = false;

fn mis(x: f32) -> f32 {
    return select(x, x * x, MIS_POWER);
}

// A path merges at MERGES_A_PATH vertices at most: the first ones from the camera where
// merging is a strategy (the first is SPPM's visible point, Hachisuka & Jensen 2009; the second
// its final gather, where light arriving through glass is dense), so that a camera subpath
// looks up the light vertices at two vertices however long it is; a merge further from the
// camera paid less than its lookup (BENCHMARKS.md "VCM").
const MERGES_A_PATH: u32 = 2u;

// What the weights of a subpath's strategies need, carried along it. The merges at the
// subpath's two latest vertices that merge are kept apart from the rest, in d_merge (x the
// latest, y the one before; their terms in d_vm, and f.vm times those in d_vc, as both grow
// alike): a camera subpath counts them always (they are its first two), a light subpath as
// many as the strategy weighed leaves to it (merges_left).
struct SubpathMis {
    d_vcm: f32,
    d_vc: f32,
    d_vm: f32,
    d_merge: vec2f,
}

// The terms of the subpath's n latest merges.
fn merge_terms(m: SubpathMis, n: u32) -> f32 {
    return select(0.0, m.d_merge.x, n > 0u) + select(0.0, m.d_merge.y, n > 1u);
}

// The merges a light subpath's side of a path may hold: those the camera's side
// (`camera_merges` of its vertices) leaves of MERGES_A_PATH, less the light subpath's own end
// where that merges (`own`).
fn merges_left(camera_merges: u32, own: bool) -> u32 {
    let left = MERGES_A_PATH - min(camera_merges, MERGES_A_PATH);
    return left - select(0u, 1u, own && left > 0u);
}

// Whether the subpath's quantities weigh the reverse density at its vertex (the other
// subpath's sampling of the direction back along it): where dVC, dVM or its merges are not 0.
// They are all 0 at a camera subpath's first vertex and without light subpaths; past a delta
// lobe dVC and dVM may be 0 where the merges are not.
fn weighs_reverse(m: SubpathMis) -> bool {
    return m.d_vc != 0.0 || m.d_vm != 0.0 || any(m.d_merge != vec2f(0.0));
}

// dVC with the subpath's n latest merges.
fn d_vc_of(m: SubpathMis, f: MisFactors, n: u32) -> f32 {
    return m.d_vc + f.vm * merge_terms(m, n);
}

// Which strategies a method uses and how often, as the factors the weights take. A strategy's
// density enters the heuristic times its count (Veach 1997 eq. 9.10: n_i p_i): merging's count
// is m eta_vcm, m the share of camera vertices that merge; a connection's the share c of camera
// vertices that connect to light vertices; next-event estimation's, emission's and light
// tracing's 1. vm = mis(m eta_vcm) where merging is used (else 0), vc = mis(1 / (m eta_vcm))
// then (else 0; it only scales dVM), connect = mis(c).
struct MisFactors {
    vc: f32,
    vm: f32,
    connect: f32,
}

// Merging's factor at a vertex: f.vm where merging there is a strategy (`merges`: where the
// vertex's material merges, bidir.wgsl's vcm_merges_at, as both subpaths see it, it is one of
// the MERGES_A_PATH nearest the camera, and not the light subpath's first: vcm_merges_light),
// else 0.
fn vm_at(f: MisFactors, merges: bool) -> f32 {
    return select(0.0, f.vm, merges);
}

// The count of the strategy a subpath's dVCM stands for at a vertex: the one that ends the
// subpath a vertex earlier and joins the rest by a connection. At the subpath's first vertex
// past its start (`first`) that joins the start itself, next-event estimation on the light's
// side and light tracing on the camera's, taken at every vertex; past it, a connection, taken
// at the share f.connect.
fn vcm_count(f: MisFactors, first: bool) -> f32 {
    return select(f.connect, 1.0, first);
}

// A light subpath leaving its light: the light sampled the point with area density direct_pdf_a
// (next-event estimation's, light choice included) and the point and direction together with
// emission_pdf_w; cos_light between the direction and the light's normal (1 for lights with
// no surface). A delta light (point, spot) cannot be hit: no strategy but those joining its
// vertex, so its d_vc is 0.
fn mis_light_start(direct_pdf_a: f32, emission_pdf_w: f32, cos_light: f32, delta: bool, f: MisFactors) -> SubpathMis {
    let d_vcm = mis(direct_pdf_a / emission_pdf_w);
    let d_vc = select(mis(cos_light / emission_pdf_w), 0.0, delta);
    return SubpathMis(d_vcm, d_vc, d_vc * f.vc, vec2f(0.0));
}

// A camera subpath leaving the camera along a direction of density camera_pdf_w (solid
// angle, per pixel area); n_light light subpaths a pass.
fn mis_camera_start(camera_pdf_w: f32, n_light: f32) -> SubpathMis {
    return SubpathMis(mis(n_light / camera_pdf_w), 0.0, 0.0, vec2f(0.0));
}

// The subpath reached a surface at distance `dist`, cos_hit between the segment and its
// normal. `finite`: false for the first segment from a light at infinity, whose density is
// not in area measure.
fn mis_hit(m: SubpathMis, dist: f32, cos_hit: f32, finite: bool) -> SubpathMis {
    var out = m;
    if finite {
        out.d_vcm *= mis(dist * dist);
    }
    let c = mis(abs(cos_hit));
    out.d_vcm /= c;
    out.d_vc /= c;
    out.d_vm /= c;
    out.d_merge /= c;
    return out;
}

// The subpath scattered at a vertex into a direction of density pdf_fwd, whose opposite the
// other subpath samples with density pdf_rev, cos_out between it and the normal; a specular
// scattering's densities are deltas, which cancel. `merges`: whether merging at the vertex is
// a strategy (Georgiev 2012, eqs. 35-37), which becomes the subpath's latest merge in d_merge,
// the latest before it the one before, an earlier one dropped; `first`: whether it is the
// subpath's first vertex past its start (vcm_count).
fn mis_scatter(m: SubpathMis, pdf_fwd: f32, pdf_rev: f32, cos_out: f32, specular: bool, merges: bool, first: bool,
    f: MisFactors) -> SubpathMis {
    if specular {
        let c = mis(abs(cos_out));
        return SubpathMis(0.0, m.d_vc * c, m.d_vm * c, m.d_merge * c);
    }
    let g = mis(abs(cos_out) / pdf_fwd);
    let rev = mis(pdf_rev);
    let joined = m.d_vcm * vcm_count(f, first);
    let d_vc = g * (m.d_vc * rev + joined);
    let d_vm = g * (m.d_vm * rev + joined * f.vc);
    let d_merge = g * select(m.d_merge * rev, vec2f(1.0, m.d_merge.x * rev), merges);
    return SubpathMis(mis(1.0 / pdf_fwd), d_vc, d_vm, d_merge);
}

// Weight of light tracing: light vertex (with `light`, reached and not yet scattered) joined
// to the camera, which would have sampled it with area density camera_pdf_a; bsdf_rev_pdf_w
// the density of the BSDF sampling the light's side given the camera's direction; `merges`
// whether the vertex merges, `first` whether it is the light subpath's first past the light.
fn mis_weight_to_camera(light: SubpathMis, camera_pdf_a: f32, bsdf_rev_pdf_w: f32, n_light: f32, merges: bool, first: bool,
    f: MisFactors) -> f32 {
    let w_light = mis(camera_pdf_a / n_light)
        * (vm_at(f, merges) + light.d_vcm * vcm_count(f, first) + d_vc_of(light, f, merges_left(0u, merges)) * mis(bsdf_rev_pdf_w));
    return 1.0 / (w_light + 1.0);
}

// Weight of emission hit by a camera subpath (`camera` updated by mis_hit at the light):
// next-event estimation would have sampled the point with direct_pdf_a, and a light subpath
// the point and the direction to the camera's previous vertex with emission_pdf_w. A merge at
// that vertex (`last_merges`, its term the latest of camera.d_merge) would take a light vertex
// straight from the light, which no light vertex merges as (bidir.wgsl's vcm_merges_light):
// no strategy, left out.
fn mis_weight_emission(camera: SubpathMis, direct_pdf_a: f32, emission_pdf_w: f32, last_merges: bool, f: MisFactors) -> f32 {
    let merges = select(merge_terms(camera, MERGES_A_PATH), camera.d_merge.y, last_merges);
    let w_camera = mis(direct_pdf_a) * camera.d_vcm + mis(emission_pdf_w) * (camera.d_vc + f.vm * merges);
    return 1.0 / (1.0 + w_camera);
}

// Weight of next-event estimation at a camera vertex: the light sampled with direct_pdf_w
// (solid angle from the vertex, light choice included; 0 for a delta light, which BSDF
// sampling cannot hit), and would have emitted towards the vertex with emission_pdf_w; the
// BSDF samples the light's direction with bsdf_pdf_w and the opposite with bsdf_rev_pdf_w;
// cos_to_light at the vertex, cos_at_light at the light; `first` whether the vertex is the
// camera subpath's first. A merge at the vertex would take a light vertex straight from the
// light: no strategy (bidir.wgsl's vcm_merges_light).
fn mis_weight_nee(camera: SubpathMis, direct_pdf_w: f32, emission_pdf_w: f32, cos_to_light: f32, cos_at_light: f32,
    bsdf_pdf_w: f32, bsdf_rev_pdf_w: f32, delta: bool, first: bool, f: MisFactors) -> f32 {
    let w_light = select(mis(bsdf_pdf_w / direct_pdf_w), 0.0, delta);
    let w_camera = mis(emission_pdf_w * abs(cos_to_light) / (direct_pdf_w * abs(cos_at_light)))
        * (camera.d_vcm * vcm_count(f, first) + d_vc_of(camera, f, MERGES_A_PATH) * mis(bsdf_rev_pdf_w));
    return 1.0 / (w_light + 1.0 + w_camera);
}

// Weight of connecting a camera vertex to a light vertex: each side's BSDF samples the other's
// vertex with density *_pdf_a (area, at the other vertex) and its own subpath's previous
// direction with *_rev_pdf_w; camera_merges whether merging at the camera vertex is a strategy
// (one of the camera subpath's first MERGES_A_PATH vertices that merge), camera_merged how many
// of the camera subpath's vertices merge, there and before; light_merges whether the light
// vertex merges (bidir.wgsl's vcm_merges_light); *_first whether it is its subpath's first
// past the start. The connection's own count is f.connect.
fn mis_weight_connection(camera: SubpathMis, light: SubpathMis, camera_pdf_a: f32, camera_rev_pdf_w: f32,
    light_pdf_a: f32, light_rev_pdf_w: f32, camera_merges: bool, camera_merged: u32, light_merges: bool, camera_first: bool,
    light_first: bool, f: MisFactors) -> f32 {
    let light_own = light_merges && merges_left(camera_merged, false) > 0u;
    let w_light = mis(camera_pdf_a) * (vm_at(f, light_own) + light.d_vcm * vcm_count(f, light_first)
        + d_vc_of(light, f, merges_left(camera_merged, light_merges)) * mis(light_rev_pdf_w));
    let w_camera = mis(light_pdf_a) * (vm_at(f, camera_merges) + camera.d_vcm * vcm_count(f, camera_first)
        + d_vc_of(camera, f, MERGES_A_PATH) * mis(camera_rev_pdf_w));
    return f.connect / (w_light + f.connect + w_camera);
}

// Weight of merging a light vertex (reached, with `light`) at a camera vertex, one of the
// camera subpath's first MERGES_A_PATH that merge, camera_merged of them up to it: the
// camera's BSDF samples the light subpath's last direction with camera_pdf_w and its own
// previous direction with camera_rev_pdf_w; *_first whether the vertex is the first of its
// subpath past the start.
fn mis_weight_merge(camera: SubpathMis, light: SubpathMis, camera_pdf_w: f32, camera_rev_pdf_w: f32, camera_merged: u32,
    camera_first: bool, light_first: bool, f: MisFactors) -> f32 {
    let w_light = light.d_vcm * vcm_count(f, light_first) * f.vc
        + (light.d_vm + merge_terms(light, merges_left(camera_merged, false))) * mis(camera_pdf_w);
    let w_camera = camera.d_vcm * vcm_count(f, camera_first) * f.vc + (camera.d_vm + merge_terms(camera, MERGES_A_PATH))
        * mis(camera_rev_pdf_w);
    return 1.0 / (w_light + 1.0 + w_camera);
}
