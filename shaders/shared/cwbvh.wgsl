// Traversal of the compressed 8-wide BVH (src/accel/cwbvh.rs; Ylitie, Karras & Laine, HPG
// 2017): `bvh_nodes` holds its nodes, five vec4u each, then from bvh.leaf_base the
// primitives of its leaves in leaf order.
//
// Node (CwNode): n0 = (p.xyz as bits, e.x | e.y << 8 | e.z << 16 | imask << 24),
// n1 = (child_base, prim_base, desc of slots 0-3, desc of slots 4-7), n2..n4 = the quantized
// lower and upper bounds of the 8 child boxes on x, y, z, one byte a slot.
//
// The ray visits a node's children in the order of its octant: interior children that the
// ray enters set bit 24 + (slot ^ oct_inv) of a hit mask, and the highest bit is taken
// first. A "group" is (first child node, remaining hit bits << 24 | imask); the stack holds
// groups with children still to visit, at most one per level. The primitives of the leaves
// the ray enters are tested as soon as their node is (their bits are the low 24 of the mask,
// at the offsets from prim_base). Mirrors CwBvh::traverse on the host step for step.

const CW_STACK_SIZE: u32 = 32u;

// The leaves' primitives, three entries each from bvh.leaf_base in bvh_nodes
// (src/gpu/baked_bvh.rs, leaf_prims): a triangle (p0, prim_ref), (e1, shape), (e2, 0); a
// sphere (center, prim_ref), (radius, shape, 0, 0), as f32 bits. One load fewer than
// prim_refs then triangles, and adjacent: 1.05x rays/s on the bunny and the 11k and 871k
// dragons (cargo bench --bench traversal); in the nodes' buffer, because the photon pass
// has no binding to spare (16 storage buffers a stage).

// Hit bits of the four children of one half of a node: `desc` their descriptions, `q_near`
// and `q_far` their near and far quantized bounds per axis (already chosen by the ray's
// direction), `p` and `e` the node's grid.
fn cw_half(desc: u32, q_near: vec3u, q_far: vec3u, scale: vec3f, b_near: vec3f, b_far: vec3f, oct_inv4: u32, t_max: f32) -> u32 {
    // The ray in the node's grid: a plane q lies at t = q scale + b (see trace_cwbvh), near
    // planes moved towards the ray's origin and far ones away from it by a bound on the
    // rounding. Four children at once; NaN (a direction component of 0) narrows nothing.
    let near_x = fma(vec4f(unpack4xU8(q_near.x)), vec4f(scale.x), vec4f(b_near.x));
    let near_y = fma(vec4f(unpack4xU8(q_near.y)), vec4f(scale.y), vec4f(b_near.y));
    let near_z = fma(vec4f(unpack4xU8(q_near.z)), vec4f(scale.z), vec4f(b_near.z));
    let far_x = fma(vec4f(unpack4xU8(q_far.x)), vec4f(scale.x), vec4f(b_far.x));
    let far_y = fma(vec4f(unpack4xU8(q_far.y)), vec4f(scale.y), vec4f(b_far.y));
    let far_z = fma(vec4f(unpack4xU8(q_far.z)), vec4f(scale.z), vec4f(b_far.z));
    var t0 = vec4f(0.0);
    var t1 = vec4f(t_max);
    t0 = select(t0, near_x, near_x > t0);
    t1 = select(t1, far_x, far_x < t1);
    t0 = select(t0, near_y, near_y > t0);
    t1 = select(t1, far_y, far_y < t1);
    t0 = select(t0, near_z, near_z > t0);
    t1 = select(t1, far_z, far_z < t1);
    let entered = t0 <= t1;
    // Per byte: interior children have bits 3 and 4 of the low five set (24 + slot), leaves
    // never (offsets below 24); an interior child's bit index is 24 + (slot ^ oct_inv), a
    // leaf's its primitives' offset; the bits set are 1 for a child node, the unary count of
    // a leaf's primitives, nothing for an empty slot.
    let inner = ((desc & (desc << 1u)) & 0x10101010u) >> 4u;
    let bit_index = unpack4xU8((desc ^ (oct_inv4 & (inner * 0xffu))) & 0x1f1f1f1fu);
    let child_bits = unpack4xU8((desc >> 5u) & 0x07070707u);
    let bits = select(vec4u(0u), child_bits << bit_index, entered);
    return bits.x | bits.y | bits.z | bits.w;
}

// The closest hit (or with any_hit, the first found) through the CWBVH, into *hit.
fn trace_cwbvh(o: vec3f, d: vec3f, inv_d: vec3f, any_hit: bool, hit: ptr<function, Hit>) {
    let negative = inv_d < vec3f(0.0);
    let oct_inv = select(4u, 0u, d.x < 0.0) | select(2u, 0u, d.y < 0.0) | select(1u, 0u, d.z < 0.0);
    let oct_inv4 = oct_inv * 0x01010101u;
    var stack: array<vec2u, CW_STACK_SIZE>;
    var sp = 0u;
    // The root as the one interior child of a virtual node.
    var group = vec2u(0u, 0x80000000u);
    loop {
        var prims = vec2u(0u);
        if (group.y & 0xff000000u) != 0u {
            let bits = group.y;
            let bit = firstLeadingBit(bits);
            group.y = bits & ~(1u << bit);
            if (group.y & 0xff000000u) != 0u {
                stack[min(sp, CW_STACK_SIZE - 1u)] = group;
                sp += 1u;
            }
            let slot = (bit - 24u) ^ oct_inv;
            let index = 5u * (group.x + countOneBits(bits & ~(0xffffffffu << slot)));
            let n0 = bvh_nodes[index];
            let n1 = bvh_nodes[index + 1u];
            let n2 = bvh_nodes[index + 2u];
            let n3 = bvh_nodes[index + 3u];
            let n4 = bvh_nodes[index + 4u];
            let p = bitcast<vec3f>(n0.xyz);
            let e = bitcast<vec3f>(vec3u(n0.w & 0xffu, (n0.w >> 8u) & 0xffu, (n0.w >> 16u) & 0xffu) << vec3u(23u));
            // Near and far bounds: lower ones near where the direction is positive.
            let lo_a = vec3u(n2.x, n3.x, n4.x);
            let lo_b = vec3u(n2.y, n3.y, n4.y);
            let hi_a = vec3u(n2.z, n3.z, n4.z);
            let hi_b = vec3u(n2.w, n3.w, n4.w);
            // Plane p + q e (q e exact) at t = (p + q e - o) inv_d = q scale + b. The rounding
            // of b, of the fused q scale + b, of inv_d, and the half ulp by which the host's
            // f32 decode p + q e may differ from the exact sum, are each within a few ulps of
            // (|p - o| + |p| + 255 e) |inv_d|: 1e-6 times that (8 ulps) bounds them all.
            let po = p - o;
            let scale = e * inv_d;
            let b = po * inv_d;
            let slack = 1e-6 * (abs(po) + abs(p) + 255.0 * e) * abs(inv_d);
            let b_near = b - slack;
            let b_far = b + slack;
            let mask = cw_half(n1.z, select(lo_a, hi_a, negative), select(hi_a, lo_a, negative), scale, b_near, b_far, oct_inv4, (*hit).t)
                | cw_half(n1.w, select(lo_b, hi_b, negative), select(hi_b, lo_b, negative), scale, b_near, b_far, oct_inv4, (*hit).t);
            group = vec2u(n1.x, (mask & 0xff000000u) | (n0.w >> 24u));
            prims = vec2u(n1.y, mask & 0x00ffffffu);
        }
        while prims.y != 0u {
            let bit = firstLeadingBit(prims.y);
            prims.y &= ~(1u << bit);
            let k = bvh.leaf_base + 3u * (prims.x + bit);
            let a = bitcast<vec4f>(bvh_nodes[k]);
            let b = bitcast<vec4f>(bvh_nodes[k + 1u]);
            let r = bitcast<u32>(a.w);
            if is_sphere(r) {
                hit_sphere(a.xyz, b.x, r, bitcast<u32>(b.y), o, d, hit);
            } else {
                hit_triangle(a.xyz, b.xyz, bitcast<vec3f>(bvh_nodes[k + 2u].xyz), r, bitcast<u32>(b.w), o, d, hit);
            }
            if any_hit && (*hit).prim_ref != 0xffffffffu {
                return;
            }
        }
        if (group.y & 0xff000000u) == 0u {
            if sp == 0u {
                break;
            }
            sp -= 1u;
            group = stack[min(sp, CW_STACK_SIZE - 1u)];
        }
    }
}
