// The light-vertex store of the bidirectional methods (bpt): each light subpath of a pass
// (light_trace.wgsl) keeps its vertices where a BSDF can be evaluated, so that camera subpaths
// (bidir_connect.wgsl) can connect to them (Veach 1997 sec. 10.2; SmallVCM's light vertices).
// Subpath i's k-th stored vertex lies at slot k n_light + i (light_vertex_slot; a subpath has at
// most max_depth of them); light_path_length[i] says how many it has. frame.photon_count
// subpaths a pass, n_light; pixel j's camera subpath connects to subpath j mod n_light.

#import types
#import scene

// A light subpath's vertex, 96 bytes (LightVertex in src/layout/records.rs): the
// surface it lies on (its material's albedo looked up again from uv), the direction back along
// the subpath, the throughput (the flux estimate beta, over the whole power, not yet divided
// by the number of subpaths), its segment count from the light, and its MIS quantities.
struct LightVertex {
    p: vec3f,
    material: u32,
    ng: vec3f,
    shape: u32,
    ns: vec3f,
    // Segments from the light to this vertex.
    length: u32,
    // Unit direction towards the subpath's previous vertex.
    w_prev: vec3f,
    d_vcm: f32,
    beta: vec3f,
    d_vc: f32,
    uv: vec2f,
    d_vm: f32,
    pad: u32,
}

@group(0) @binding(29) var<storage, read_write> light_vertices: array<LightVertex>;
@group(0) @binding(30) var<storage, read_write> light_path_length: array<u32>;
// vcm: each stored vertex also as a point of the radius (frame.global_radius), appended
// (merge_count of them this pass; `normal` holds the vertex's index in light_vertices), which
// SPPM's grid build (grid_count.wgsl, grid_fill.wgsl) lists in the hashed grid's buckets for
// merging (bidir_connect.wgsl), over the dispatch merge_setup.wgsl sizes.
@group(0) @binding(8) var<storage, read_write> visible_points: array<VisiblePoint>;
@group(0) @binding(32) var<storage, read_write> merge_count: array<atomic<u32>>;

// The slot of subpath i's k-th stored vertex: the subpaths' k-th vertices side by side, so that
// the vertices a pass stores (a few a subpath, of max_depth slots each) lie together at the
// store's start rather than spread over all of it, which merging reads at random (at
// max_depth 64 a spread store cost merging alone 10% of its pass: docs/journal/session-25.md).
fn light_vertex_slot(i: u32, k: u32) -> u32 {
    return k * frame.photon_count + i;
}

// The surface a stored vertex lies on.
fn light_vertex_surface(v: LightVertex) -> Surface {
    return Surface(v.p, v.ng, v.ns, v.material, v.shape, v.uv);
}
