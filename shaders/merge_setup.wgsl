// vcm, after a pass's light subpaths (light_trace.wgsl): the grid build's dispatch over the
// merge points they appended (merge_count of them, shared/light_vertex.wgsl), as indirect
// arguments, and radius 0 for the points past the count in the last workgroup, which hold an
// earlier pass's points (SPPM's grid kernels then list none of them).

#import types
#import scene
#import light_vertex
@group(0) @binding(33) var<storage, read_write> merge_args: array<u32>;

@compute @workgroup_size(64)
fn merge_setup(@builtin(local_invocation_index) t: u32) {
    let count = min(atomicLoad(&merge_count[0]), frame.vp_count);
    let groups = (count + 63u) / 64u;
    if t == 0u {
        merge_args[0] = groups;
        merge_args[1] = 1u;
        merge_args[2] = 1u;
    }
    let i = count + t;
    if i < min(groups * 64u, frame.vp_count) {
        visible_points[i].radius = 0.0;
    }
}
