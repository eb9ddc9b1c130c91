// vcm, after the grid build: each bucket's entries made merge entries (the light vertex's
// position and its slot, light_vertex.wgsl: a merge point's `normal`), in ascending order of
// key (light_vertex_key: subpath and vertex, which unlike the slot does not depend on which
// thread took a slot first). The grid build (grid_fill.wgsl) lists a bucket's points in an
// order that depends on timing, and the merge points are appended (light_trace.wgsl) in the
// order the subpaths reach them; merging (bidir_connect.wgsl's merge_light_vertices) sums in
// the bucket's order, so only a fixed order makes a seed's image the same bit for bit. The
// position beside the slot lets merging test a candidate's distance from the bucket's own
// entries, read in order, rather than from its light vertex, read at random (most candidates
// lie beyond the radius). One thread a bucket, an insertion sort by key (the entries and the
// bucket's point indices together), then each key replaced by its slot: a bucket lists tens
// of points.

#import types
#import light_vertex

@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read_write> grid_entries: array<u32>;
// A bucket's light vertices: position (xyz) and slot (w, its bits).
@group(0) @binding(35) var<storage, read_write> merge_entries: array<vec4f>;

@compute @workgroup_size(64)
fn merge_order(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let h = gid.x + gid.y * groups.x * 64u;
    if h + 1u >= arrayLength(&grid_cell_start) {
        return;
    }
    let first = grid_cell_start[h];
    let end = min(grid_cell_start[h + 1u], min(arrayLength(&grid_entries), arrayLength(&merge_entries)));
    for (var i = first; i < end; i++) {
        let point = visible_points[grid_entries[i]];
        merge_entries[i] = vec4f(point.p, point.weight.x);
    }
    for (var i = first + 1u; i < end; i++) {
        let entry = merge_entries[i];
        let point = grid_entries[i];
        let key = bitcast<u32>(entry.w);
        var j = i;
        while j > first && bitcast<u32>(merge_entries[j - 1u].w) > key {
            merge_entries[j] = merge_entries[j - 1u];
            grid_entries[j] = grid_entries[j - 1u];
            j--;
        }
        merge_entries[j] = entry;
        grid_entries[j] = point;
    }
    for (var i = first; i < end; i++) {
        merge_entries[i].w = bitcast<f32>(visible_points[grid_entries[i]].normal);
    }
}
