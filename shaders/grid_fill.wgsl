// Grid build, step 4 of 4: list each point in its buckets. Slots are taken by counting each
// bucket down, so a bucket's order depends on timing; the deposits are summed in fixed point
// and do not depend on it.

#import grid_build

@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read_write> grid_entries: array<u32>;

@compute @workgroup_size(64)
fn grid_fill(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let walk = point_walk(gid, groups);
    for (var k = 0u; k < 8u; k++) {
        if !visits(walk.buckets, k) {
            continue;
        }
        let h = walk.buckets.h[k];
        let slot = atomicSub(&grid_cell_count[h], 1u) - 1u;
        let e = grid_cell_start[h] + slot;
        if e < arrayLength(&grid_entries) {
            grid_entries[e] = walk.index;
        }
    }
}
