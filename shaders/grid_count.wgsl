// Grid build, step 2 of 4: count the points listed in each bucket.

#import grid_build

@compute @workgroup_size(64)
fn grid_count(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let b = point_walk(gid, groups).buckets;
    for (var k = 0u; k < 8u; k++) {
        if visits(b, k) {
            atomicAdd(&grid_cell_count[b.h[k]], 1u);
        }
    }
}
