// lanes.wgsl for a device without subgroup operations: every lane is a group of one.

fn lane_rank() -> u32 {
    return 0u;
}

fn lane_count() -> u32 {
    return 1u;
}

fn lane_ballot(b: bool) -> vec4u {
    return vec4u(select(0u, 1u, b), 0u, 0u, 0u);
}

fn lane_shuffle_u(x: u32, lane: u32) -> u32 {
    return x;
}

fn lane_shuffle_u2(x: vec2u, lane: u32) -> vec2u {
    return x;
}

fn lane_shuffle_f3(x: vec3f, lane: u32) -> vec3f {
    return x;
}
