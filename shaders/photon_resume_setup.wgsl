// After the gather (one thread): the sizes of the dispatches that finish the photon threads
// which stopped for want of room for a hit (photon_pass.wgsl). With any such thread, the grid
// of visible points is built (grid_count and grid_fill over the points) and photon_pass
// resumes them; with none, all three dispatches are empty, and a pass costs nothing for them.

#import types

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(24) var<storage, read> photon_hit_lists: array<u32>;
// Workgroup counts (x, y, z) from word ARGS_GRID for grid_count and grid_fill, ARGS_RESUME for
// photon_pass resuming, ARGS_SCAN for grid_scan (one workgroup). Then, summed over the pass
// (the host clears them when it starts): word ARGS_COUNTS, the hits gathered; the next, the
// threads resumed. The host's byte offsets are these times 4 (src/integrators/sppm.rs).
@group(0) @binding(26) var<storage, read_write> photon_resume_args: array<u32>;
const ARGS_GRID: u32 = 0u;
const ARGS_RESUME: u32 = 3u;
const ARGS_SCAN: u32 = 6u;
const ARGS_COUNTS: u32 = 9u;

// Workgroups of 64 for `threads` threads, as the host lays them out (Kernel::dispatch):
// up to 65535 along x, the rest along y.
fn groups_for(threads: u32) -> vec3u {
    let groups = (threads + 63u) / 64u;
    if groups == 0u {
        return vec3u(0u, 1u, 1u);
    }
    let x = min(groups, 65535u);
    return vec3u(x, (groups + x - 1u) / x, 1u);
}

@compute @workgroup_size(1)
fn photon_resume_setup() {
    let stopped = photon_hit_lists[1];
    // The count of hits goes past the capacity by the attempts that found no room.
    photon_resume_args[ARGS_COUNTS] += min(photon_hit_lists[0], frame.hit_capacity);
    photon_resume_args[ARGS_COUNTS + 1u] += stopped;
    let grid = select(vec3u(0u, 1u, 1u), groups_for(frame.vp_count), stopped > 0u);
    let resume = groups_for(stopped);
    photon_resume_args[ARGS_GRID] = grid.x;
    photon_resume_args[ARGS_GRID + 1u] = grid.y;
    photon_resume_args[ARGS_GRID + 2u] = grid.z;
    photon_resume_args[ARGS_RESUME] = resume.x;
    photon_resume_args[ARGS_RESUME + 1u] = resume.y;
    photon_resume_args[ARGS_RESUME + 2u] = resume.z;
    photon_resume_args[ARGS_SCAN] = select(0u, 1u, stopped > 0u);
    photon_resume_args[ARGS_SCAN + 1u] = 1u;
    photon_resume_args[ARGS_SCAN + 2u] = 1u;
}
