// The lanes of a SIMD group working together, through subgroup operations: over the lanes
// active at the call, their rank, their count, which of them hold a condition, and a value
// taken from one of them. Kernels built for a device without subgroups import
// lanes_single.wgsl instead (src/gpu/kernel.rs), where every lane is a group of its own.

// This lane's rank among the active lanes.
fn lane_rank() -> u32 {
    return subgroupExclusiveAdd(1u);
}

// How many lanes are active.
fn lane_count() -> u32 {
    return subgroupAdd(1u);
}

// Bit i of word i / 32 is set where lane i is active and holds b.
fn lane_ballot(b: bool) -> vec4u {
    return subgroupBallot(b);
}

fn lane_shuffle_u(x: u32, lane: u32) -> u32 {
    return subgroupShuffle(x, lane);
}

fn lane_shuffle_u2(x: vec2u, lane: u32) -> vec2u {
    return subgroupShuffle(x, lane);
}

fn lane_shuffle_f3(x: vec3f, lane: u32) -> vec3f {
    return subgroupShuffle(x, lane);
}
