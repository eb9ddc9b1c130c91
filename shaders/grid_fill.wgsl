// Grid build, step 4 of 4: list each point in its buckets. Slots are taken by counting each
// bucket down, so a bucket's order depends on timing; the deposits are summed in fixed point
// and do not depend on it.

#import types
#import grid

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(2) var<storage, read> grid_params: GridParams;
@group(0) @binding(3) var<storage, read_write> grid_cell_count: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read> visible_points: array<VisiblePoint>;
@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read_write> grid_entries: array<u32>;

@compute @workgroup_size(64)
fn grid_fill(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if index >= frame.vp_count {
        return;
    }
    let q = visible_points[index];
    let b = point_buckets(grid_params, q.p, q.radius);
    for (var k = 0u; k < 8u; k++) {
        if ((b.keep >> k) & 1u) == 0u {
            continue;
        }
        let h = b.h[k];
        let slot = atomicSub(&grid_cell_count[h], 1u) - 1u;
        let e = grid_cell_start[h] + slot;
        if e < arrayLength(&grid_entries) {
            grid_entries[e] = index;
        }
    }
}
