// Grid build, step 2 of 4: count the points listed in each bucket.

#import types
#import grid

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(2) var<storage, read> grid_params: GridParams;
@group(0) @binding(3) var<storage, read_write> grid_cell_count: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;

@compute @workgroup_size(64)
fn grid_count(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let q = visible_points[index];
    let b = point_buckets(grid_params, q.p, q.radius);
    for (var k = 0u; k < 8u; k++) {
        if ((b.keep >> k) & 1u) != 0u {
            atomicAdd(&grid_cell_count[b.h[k]], 1u);
        }
    }
}
