// The light-vertex store of the bidirectional methods (bpt): each light subpath of a pass
// (light_trace.wgsl) keeps its vertices where a BSDF can be evaluated, so that camera subpaths
// (bidir_connect.wgsl) can connect to them (Veach 1997 sec. 10.2; SmallVCM's light vertices).
// The store is a cache of a pass's vertices (Davidovic et al. 2014, sec. 4.1, "light vertex
// cache"): a vertex takes the next free slot (light_vertex_count[0]), so the store holds what the
// pass's subpaths keep (a few vertices each) rather than max_depth slots a subpath.
// light_path_first[i] is subpath i's first vertex, each vertex's `next` the one after it
// (LIGHT_VERTEX_NONE ends the list). frame.photon_count subpaths a pass, n_light; pixel j's
// camera subpath connects to subpath j mod n_light.

#import types
#import scene

// A light subpath's vertex, 112 bytes (LightVertex in src/layout/records.rs): the
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
    // The slot of the subpath's next stored vertex, or LIGHT_VERTEX_NONE.
    next: u32,
    // The subpath's two latest merges, apart from d_vc and d_vm (vcm.wgsl's SubpathMis).
    d_merge: vec2f,
}

// No light vertex: the end of a subpath's list.
const LIGHT_VERTEX_NONE: u32 = 0xffffffffu;

@group(0) @binding(29) var<storage, read_write> light_vertices: array<LightVertex>;
@group(0) @binding(30) var<storage, read_write> light_path_first: array<u32>;
// The slots the pass's vertices took ([0], cleared each pass; past the store's length they
// were not kept) and the vertices not kept over the render ([1]), which the host reports.
@group(0) @binding(36) var<storage, read_write> light_vertex_count: array<atomic<u32>>;
// vcm: each stored vertex that merges (bidir.wgsl's vcm_merges_light) also as a point of the
// radius (frame.global_radius), appended
// (merge_count of them this pass; `normal` holds the vertex's slot in light_vertices, and
// `weight.x` the bits of its key, light_vertex_key), which
// SPPM's grid build (grid_count.wgsl, grid_fill.wgsl) lists in the hashed grid's buckets for
// merging (bidir_connect.wgsl), over the dispatch merge_setup.wgsl sizes.
@group(0) @binding(8) var<storage, read_write> visible_points: array<VisiblePoint>;
@group(0) @binding(32) var<storage, read_write> merge_count: array<atomic<u32>>;

// The order in which merging sums a bucket's vertices (merge_order.wgsl): subpath i's k-th
// stored vertex, the subpaths' k-th vertices side by side (light.rs bounds the subpaths so that
// keys fit 32 bits). Slots depend on which thread took one first; keys do not, so a seed's
// image is the same bit for bit.
fn light_vertex_key(i: u32, k: u32) -> u32 {
    return k * frame.photon_count + i;
}

// The surface a stored vertex lies on.
fn light_vertex_surface(v: LightVertex) -> Surface {
    return Surface(v.p, v.ng, v.ns, v.material, v.shape, v.uv);
}
