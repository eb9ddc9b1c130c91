// Traversal of the compressed 8-wide BVH (src/accel/cwbvh.rs; Ylitie, Karras & Laine, HPG
// 2017), read from the same bindings as the binary tree: `bvh_nodes` holds its nodes, five
// vec4u each, and `prim_refs` its primitive references in leaf order.
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

// Hit bits of the four children of one half of a node: `desc` their descriptions, `q_near`
// and `q_far` their near and far quantized bounds per axis (already chosen by the ray's
// direction), `p` and `e` the node's grid.
fn cw_half(desc: u32, q_near: vec3u, q_far: vec3u, p: vec3f, e: vec3f, o: vec3f, inv_d: vec3f, oct_inv4: u32, t_max: f32) -> u32 {
    // Decoded bounds p + q e (the product is exact) then the slab test of intersect_box, four
    // children at once.
    let near_x = (p.x + vec4f(unpack4xU8(q_near.x)) * e.x - o.x) * inv_d.x;
    let near_y = (p.y + vec4f(unpack4xU8(q_near.y)) * e.y - o.y) * inv_d.y;
    let near_z = (p.z + vec4f(unpack4xU8(q_near.z)) * e.z - o.z) * inv_d.z;
    let far_x = (p.x + vec4f(unpack4xU8(q_far.x)) * e.x - o.x) * inv_d.x * 1.0000004;
    let far_y = (p.y + vec4f(unpack4xU8(q_far.y)) * e.y - o.y) * inv_d.y * 1.0000004;
    let far_z = (p.z + vec4f(unpack4xU8(q_far.z)) * e.z - o.z) * inv_d.z * 1.0000004;
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
            let mask = cw_half(n1.z, select(lo_a, hi_a, negative), select(hi_a, lo_a, negative), p, e, o, inv_d, oct_inv4, (*hit).t)
                | cw_half(n1.w, select(lo_b, hi_b, negative), select(hi_b, lo_b, negative), p, e, o, inv_d, oct_inv4, (*hit).t);
            group = vec2u(n1.x, (mask & 0xff000000u) | (n0.w >> 24u));
            prims = vec2u(n1.y, mask & 0x00ffffffu);
        }
        while prims.y != 0u {
            let bit = firstLeadingBit(prims.y);
            prims.y &= ~(1u << bit);
            let r = prim_refs[prims.x + bit];
            if is_sphere(r) {
                let sphere = spheres[r & ~SPHERE_BIT];
                hit_sphere(sphere.center, sphere.radius, r, sphere.shape, o, d, hit);
            } else {
                let tri = triangles[r];
                hit_triangle(tri.p0, tri.e1, tri.e2, r, tri.shape, o, d, hit);
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
