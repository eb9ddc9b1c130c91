// Grid build, step 2 of 4: count the points listed in each bucket.

#import types
#import grid

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(2) var<storage, read> grid_params: GridParams;
@group(0) @binding(3) var<storage, read_write> grid_cell_count: array<atomic<u32>>;
@group(0) @binding(9) var<storage, read> vp_points: array<vec4f>;

@compute @workgroup_size(64)
fn grid_count(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let b = point_buckets(grid_params, vp_points[index]);
    for (var i = 0u; i < b.count; i++) {
        atomicAdd(&grid_cell_count[b.h[i]], 1u);
    }
}
