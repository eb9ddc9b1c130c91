// vcm, after the grid build: each bucket's entries made merge entries (the light vertex's
// position and its slot, light_vertex.wgsl: a merge point's `normal`), in ascending order of
// key (light_vertex_key: subpath and vertex, which unlike the slot does not depend on which
// thread took a slot first). The grid build (grid_fill.wgsl) lists a bucket's points in an
// order that depends on timing, and the merge points are appended (light_trace.wgsl) in the
// order the subpaths reach them; merging (bidir_connect.wgsl's merge_light_vertices) sums in
// the bucket's order, so only a fixed order makes a seed's image the same bit for bit. The
// position beside the slot lets merging test a candidate's distance from the bucket's own
// entries, read in order, rather than from its light vertex, read at random (most candidates
// lie beyond the radius). One thread a bucket sorts the entries by key, with the bucket's
// point indices, then writes each entry's slot for its key: an insertion sort for a short
// bucket, a heapsort (Williams 1964) for a long one, whose steps grow as b log b rather than
// b^2 (a bucket lists a few entries at one light subpath for 4 pixels, tens to hundreds at
// several a pixel, where insertion sorting took most of the pass: docs/journal/session-28.md).
// Each light vertex is listed once, in its own cell's bucket (grid_build.wgsl's
// LISTS_OWN_CELL): in every bucket its radius reaches, as SPPM's points are, it made the
// buckets 8 times as long and this sort a tenth of the pass (docs/journal/session-30.md).

#import types
#import light_vertex

@group(0) @binding(12) var<storage, read> grid_cell_start: array<u32>;
@group(0) @binding(13) var<storage, read_write> grid_entries: array<u32>;
// A bucket's light vertices: position (xyz) and slot (w, its bits).
@group(0) @binding(35) var<storage, read_write> merge_entries: array<vec4f>;

// Entries up to which a bucket is insertion sorted.
const SHORT_BUCKET: u32 = 64u;

fn key_of(e: u32) -> u32 {
    return bitcast<u32>(merge_entries[e].w);
}

fn swap_entries(a: u32, b: u32) {
    let entry = merge_entries[a];
    merge_entries[a] = merge_entries[b];
    merge_entries[b] = entry;
    let point = grid_entries[a];
    grid_entries[a] = grid_entries[b];
    grid_entries[b] = point;
}

fn insertion_sort(first: u32, end: u32) {
    for (var i = first + 1u; i < end; i++) {
        let entry = merge_entries[i];
        let point = grid_entries[i];
        let key = bitcast<u32>(entry.w);
        var j = i;
        while j > first && key_of(j - 1u) > key {
            merge_entries[j] = merge_entries[j - 1u];
            grid_entries[j] = grid_entries[j - 1u];
            j--;
        }
        merge_entries[j] = entry;
        grid_entries[j] = point;
    }
}

// The heap of the `len` entries from `first` restored below `root` (a max-heap by key).
fn sift_down(first: u32, root_start: u32, len: u32) {
    var root = root_start;
    loop {
        var child = 2u * root + 1u;
        if child >= len {
            break;
        }
        if child + 1u < len && key_of(first + child + 1u) > key_of(first + child) {
            child += 1u;
        }
        if key_of(first + child) <= key_of(first + root) {
            break;
        }
        swap_entries(first + root, first + child);
        root = child;
    }
}

fn heapsort(first: u32, len: u32) {
    for (var i = len / 2u; i > 0u; i--) {
        sift_down(first, i - 1u, len);
    }
    for (var n = len - 1u; n > 0u; n--) {
        swap_entries(first, first + n);
        sift_down(first, 0u, n);
    }
}

@compute @workgroup_size(64)
fn merge_order(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let h = gid.x + gid.y * groups.x * 64u;
    if h + 1u >= arrayLength(&grid_cell_start) {
        return;
    }
    let first = grid_cell_start[h];
    let end = min(grid_cell_start[h + 1u], min(arrayLength(&grid_entries), arrayLength(&merge_entries)));
    if end <= first {
        return;
    }
    for (var i = first; i < end; i++) {
        let point = visible_points[grid_entries[i]];
        merge_entries[i] = vec4f(point.p, point.weight.x);
    }
    if end - first <= SHORT_BUCKET {
        insertion_sort(first, end);
    } else {
        heapsort(first, end - first);
    }
    for (var i = first; i < end; i++) {
        merge_entries[i].w = bitcast<f32>(visible_points[grid_entries[i]].normal);
    }
}
