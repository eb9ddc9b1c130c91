// Grid build, step 3 of 4 (one workgroup): bucket offsets, the exclusive prefix sum of the
// counts. Each of the 256 threads sums a contiguous run of buckets, the run totals are scanned
// in shared memory (Hillis & Steele 1986), and each thread then writes its run's offsets.

#import types

@group(0) @binding(3) var<storage, read> grid_cell_count: array<u32>;
@group(0) @binding(12) var<storage, read_write> grid_cell_start: array<u32>;

const THREADS: u32 = 256u;

var<workgroup> totals: array<u32, THREADS>;

@compute @workgroup_size(256)
fn grid_scan(@builtin(local_invocation_index) t: u32) {
    let n = arrayLength(&grid_cell_count);
    let run = (n + THREADS - 1u) / THREADS;
    let first = min(t * run, n);
    let end = min(first + run, n);
    var sum = 0u;
    for (var i = first; i < end; i++) {
        sum += grid_cell_count[i];
    }
    totals[t] = sum;
    workgroupBarrier();
    for (var offset = 1u; offset < THREADS; offset *= 2u) {
        let add = select(0u, totals[t - offset], t >= offset);
        workgroupBarrier();
        totals[t] += add;
        workgroupBarrier();
    }
    // totals[t] is now inclusive; the run starts after the runs before it.
    var start = totals[t] - sum;
    for (var i = first; i < end; i++) {
        grid_cell_start[i] = start;
        start += grid_cell_count[i];
    }
    if t == THREADS - 1u {
        grid_cell_start[n] = totals[t];
    }
}
