// The scene as every tracing kernel sees it: geometry, BVH and materials, and the closest-hit
// query over them.

@group(0) @binding(0) var<uniform> frame: Frame;
// BvhNode (shared/types.wgsl) read as two vec4u, (box_a, child_a) and (box_b, child_b): two
// loads a node rather than one per member (a CPU driver loads lane by lane, per load).
@group(0) @binding(1) var<storage, read> bvh_nodes: array<vec4u>;
@group(0) @binding(2) var<storage, read> prim_refs: array<u32>;
@group(0) @binding(3) var<storage, read> triangles: array<Triangle>;
@group(0) @binding(4) var<storage, read> spheres: array<Sphere>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> attributes: array<vec4f>;
@group(0) @binding(7) var<storage, read> shapes: array<Shape>;
@group(0) @binding(18) var<storage, read> texels: array<vec4f>;
@group(0) @binding(20) var<uniform> bvh: BvhParams;

const BVH_STACK_SIZE: u32 = 64u;

// Which layout `bvh_nodes` and `prim_refs` hold: 0 reads it from bvh.tree_kind at run time, 1 is
// the binary tree, 2 the CWBVH (src/accel/cwbvh.rs), set per scene by the host so that the
// other traversal is compiled out.
override BVH_LAYOUT: u32 = 0u;

fn uses_cwbvh() -> bool {
    return BVH_LAYOUT == 2u || (BVH_LAYOUT == 0u && bvh.tree_kind == 1u);
}

#import cwbvh

// What the scene has, set by the host per scene (src/gpu/features.rs); code for what it lacks
// is folded away when the pipeline is compiled. CPU drivers run both sides of a branch,
// masked, so without this every bounce would pay for every feature. The defaults build
// kernels that handle any scene.
override USES_TRIANGLES: bool = true;
override USES_SPHERES: bool = true;
override USES_MOTION: bool = true;
override USES_SHADING_NORMALS: bool = true;
override USES_UVS: bool = true;
override USES_TEXTURES: bool = true;

// Whether primitive reference r is a sphere, decided without a load when the scene holds
// only one kind of primitive.
fn is_sphere(r: u32) -> bool {
    return USES_SPHERES && (!USES_TRIANGLES || (r & SPHERE_BIT) != 0u);
}

struct Hit {
    t: f32,
    prim_ref: u32,
    // Barycentrics of the triangle's second and third vertex.
    b: vec2f,
}

// Moller & Trumbore 1997. Returns (t, b1, b2); t < 0 when there is no hit in (0, t_max).
fn intersect_triangle(tri: Triangle, o: vec3f, d: vec3f, t_max: f32) -> vec3f {
    let pv = cross(d, tri.e2);
    let det = dot(tri.e1, pv);
    if det == 0.0 {
        return vec3f(-1.0);
    }
    let inv_det = 1.0 / det;
    let tv = o - tri.p0;
    let b1 = dot(tv, pv) * inv_det;
    if b1 < 0.0 || b1 > 1.0 {
        return vec3f(-1.0);
    }
    let qv = cross(tv, tri.e1);
    let b2 = dot(d, qv) * inv_det;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return vec3f(-1.0);
    }
    let t = dot(tri.e2, qv) * inv_det;
    if t <= 0.0 || t >= t_max {
        return vec3f(-1.0);
    }
    return vec3f(t, b1, b2);
}

// Nearest root in (0, t_max), the far one when the origin is inside; -1 for none. The
// discriminant is formed as in Haines et al., Ray Tracing Gems ch. 7, for precision.
fn intersect_sphere(s: Sphere, o: vec3f, d: vec3f, t_max: f32) -> f32 {
    let oc = o - s.center;
    let a = dot(d, d);
    let b = dot(oc, d) / a;
    let perp = oc - b * d;
    let disc = s.radius * s.radius - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let h = sqrt(a * disc) / a;
    let t0 = -b - h;
    let t1 = -b + h;
    if t0 > 0.0 && t0 < t_max {
        return t0;
    }
    if t1 > 0.0 && t1 < t_max {
        return t1;
    }
    return -1.0;
}

// Slab test; returns the entry distance, or a value >= t_max when the box is missed. Near and
// far planes are picked by the direction's sign, and the interval is narrowed by comparisons,
// which skip the NaN of 0 * inf (a ray in a slab's plane) and keep an inverted (empty) box
// empty; min and max would do neither. Mirrors `slab_test` in src/accel/bvh.rs.
fn intersect_box(lo: vec3f, hi: vec3f, o: vec3f, inv_d: vec3f, t_max: f32) -> f32 {
    let negative = inv_d < vec3f(0.0);
    let t_near = (select(lo, hi, negative) - o) * inv_d;
    // Padded as in pbrt-v3 sec. 3.9.1, so rounding cannot lose a box the ray grazes.
    let t_far = (select(hi, lo, negative) - o) * inv_d * 1.0000004;
    var t0 = 0.0;
    var t1 = t_max;
    for (var axis = 0; axis < 3; axis++) {
        t0 = select(t0, t_near[axis], t_near[axis] > t0);
        t1 = select(t1, t_far[axis], t_far[axis] < t1);
    }
    return select(t_max, t0, t0 <= t1);
}

// The ray origin in the rest frame of a shape that moves: at shutter time frame.time the shape
// sits at rest position + velocity * time, so the ray moves the other way instead. The
// code is compiled only for scenes with motion.
fn origin_at_rest(o: vec3f, shape: u32) -> vec3f {
    if !USES_MOTION {
        return o;
    }
    return o - shapes[shape].velocity * frame.time;
}

// Where a shape is displaced to at the pass's shutter time.
fn displacement(shape: u32) -> vec3f {
    if !USES_MOTION {
        return vec3f(0.0);
    }
    return shapes[shape].velocity * frame.time;
}

// Entry distance of the ray into the child box q (quantized, see BvhNode), or t_max when
// it misses the box or the box is empty.
fn intersect_child(q: vec3u, o: vec3f, inv_d: vec3f, t_max: f32) -> f32 {
    let lo = vec3f(f32(q.x & 0xffffu), f32(q.x >> 16u), f32(q.y & 0xffffu));
    let hi = vec3f(f32(q.y >> 16u), f32(q.z & 0xffffu), f32(q.z >> 16u));
    return intersect_box(bvh.origin + lo * bvh.scale, bvh.origin + hi * bvh.scale, o, inv_d, t_max);
}

// Whether the ray enters the box before t_max (the baked traversal's box test).
fn enters(lo: vec3f, hi: vec3f, o: vec3f, inv_d: vec3f, t_max: f32) -> bool {
    return intersect_box(lo, hi, o, inv_d, t_max) < t_max;
}

// Keep the triangle (p0, e1, e2) as the hit if it is nearer (the leaves of both traversals).
fn hit_triangle(p0: vec3f, e1: vec3f, e2: vec3f, prim_ref: u32, shape: u32, o: vec3f, d: vec3f, hit: ptr<function, Hit>) {
    let tb = intersect_triangle(Triangle(p0, 0u, e1, shape, e2, 0u), origin_at_rest(o, shape), d, (*hit).t);
    if tb.x > 0.0 {
        *hit = Hit(tb.x, prim_ref, tb.yz);
    }
}

// Keep the sphere as the hit if it is nearer.
fn hit_sphere(center: vec3f, radius: f32, prim_ref: u32, shape: u32, o: vec3f, d: vec3f, hit: ptr<function, Hit>) {
    let t = intersect_sphere(Sphere(center, radius, 0u, shape, 0u, 0u), origin_at_rest(o, shape), d, (*hit).t);
    if t > 0.0 {
        *hit = Hit(t, prim_ref, vec2f(0.0));
    }
}

// A small scene's BVH and primitives as code (src/gpu/baked_bvh.rs replaces this function
// when it builds the kernels of such a scene): true when it traced the ray.
fn trace_baked(o: vec3f, d: vec3f, inv_d: vec3f, hit: ptr<function, Hit>) -> bool { return false; }

// Closest hit along o + t d for t in (0, t_max); hit.prim_ref is 0xffffffff on a miss.
fn trace_closest(o: vec3f, d: vec3f, t_max: f32) -> Hit {
    return trace(o, d, t_max, false);
}

// Whether anything lies along o + t d for t in (0, t_max): the traversal stops at the first
// hit it finds (shadow rays).
fn occluded(o: vec3f, d: vec3f, t_max: f32) -> bool {
    return trace(o, d, t_max, true).prim_ref != 0xffffffffu;
}

// The closest hit, or with any_hit the first one found (a constant at every call, so each
// call compiles to one of the two). The stack holds child references whose boxes the ray
// entered when they were pushed.
fn trace(o: vec3f, d: vec3f, t_max_in: f32, any_hit: bool) -> Hit {
    var hit = Hit(t_max_in, 0xffffffffu, vec2f(0.0));
    let inv_d = 1.0 / d;
    if trace_baked(o, d, inv_d, &hit) {
        return hit;
    }
    if uses_cwbvh() {
        trace_cwbvh(o, d, inv_d, any_hit, &hit);
        return hit;
    }
    var stack: array<u32, BVH_STACK_SIZE>;
    // The root (node 0) is always interior; an empty scene's has two empty children.
    stack[0] = 0u;
    var sp = 1u;
    while sp > 0u {
        sp -= 1u;
        let r = stack[sp];
        if (r & LEAF_BIT) != 0u {
            let first = r & LEAF_FIRST_MASK;
            let end = first + ((r >> LEAF_COUNT_SHIFT) & 0xfu);
            for (var i = first; i < end; i++) {
                let p = prim_refs[i];
                if is_sphere(p) {
                    let sphere = spheres[p & ~SPHERE_BIT];
                    hit_sphere(sphere.center, sphere.radius, p, sphere.shape, o, d, &hit);
                } else {
                    let tri = triangles[p];
                    hit_triangle(tri.p0, tri.e1, tri.e2, p, tri.shape, o, d, &hit);
                }
            }
            if any_hit && hit.prim_ref != 0xffffffffu {
                break;
            }
            continue;
        }
        // Both children's boxes are in the node.
        let node_a = bvh_nodes[2u * r];
        let node_b = bvh_nodes[2u * r + 1u];
        let node = BvhNode(node_a.xyz, node_a.w, node_b.xyz, node_b.w);
        let t_a = intersect_child(node.box_a, o, inv_d, hit.t);
        let t_b = intersect_child(node.box_b, o, inv_d, hit.t);
        let hit_a = t_a < hit.t;
        let hit_b = t_b < hit.t;
        // The children entered, the nearer pushed last (popped first), with two stores
        // whatever was hit: branches would each store lane by lane on a CPU driver. A slot
        // past the count is overwritten later; with room for one of two, the nearer goes.
        let count = select(0u, 1u, hit_a) + select(0u, 1u, hit_b);
        let a_nearer = t_a <= t_b;
        let near = select(node.child_b, node.child_a, a_nearer);
        let far = select(node.child_a, node.child_b, a_nearer);
        let only = select(node.child_b, node.child_a, hit_a);
        if sp < BVH_STACK_SIZE {
            let both_fit = sp + 2u <= BVH_STACK_SIZE;
            stack[sp] = select(only, select(near, far, both_fit), hit_a && hit_b);
            stack[min(sp + 1u, BVH_STACK_SIZE - 1u)] = near;
            sp = min(sp + count, BVH_STACK_SIZE);
        }
    }
    return hit;
}

// What a path needs to know where it hit.
struct Surface {
    p: vec3f,
    // Geometric normal: cross(e1, e2) for triangles, outward for spheres.
    ng: vec3f,
    // Shading normal, on the same side as ng.
    ns: vec3f,
    material: u32,
    shape: u32,
    // Texture coordinates (s, t); zero where the material has no texture.
    uv: vec2f,
}

fn surface_at(hit: Hit, o: vec3f, d: vec3f) -> Surface {
    if is_sphere(hit.prim_ref) {
        let s = spheres[hit.prim_ref & ~SPHERE_BIT];
        let center = s.center + displacement(s.shape);
        let n = normalize(o + hit.t * d - center);
        // uv = (phi / 2 pi, theta / pi) of the normal in the sphere's frame (Mitsuba's
        // sphere; TOML's frame makes s the longitude about +y from +z towards +x and t the
        // latitude from the bottom pole, as in docs/guide/scene-format.md).
        var uv = vec2f(0.0);
        if USES_TEXTURES && (s.attributes & HAS_UVS) != 0u {
            let a = s.attributes & ATTRIBUTE_INDEX_MASK;
            let l = vec3f(dot(attributes[a].xyz, n), dot(attributes[a + 1u].xyz, n), dot(attributes[a + 2u].xyz, n));
            let phi = atan2(l.y, l.x);
            uv = vec2f(select(phi, phi + 2.0 * PI, phi < 0.0) * (0.5 * INV_PI), acos(clamp(l.z, -1.0, 1.0)) * INV_PI);
        }
        // Reproject onto the surface to remove the error of o + t d.
        return Surface(center + s.radius * n, n, n, s.material, s.shape, uv);
    }
    let tri = triangles[hit.prim_ref];
    let p = tri.p0 + hit.b.x * tri.e1 + hit.b.y * tri.e2 + displacement(tri.shape);
    let ng = normalize(cross(tri.e1, tri.e2));
    var ns = ng;
    var uv = vec2f(0.0);
    let b0 = 1.0 - hit.b.x - hit.b.y;
    var a = tri.attributes & ATTRIBUTE_INDEX_MASK;
    if USES_SHADING_NORMALS && (tri.attributes & HAS_NORMALS) != 0u {
        let n = b0 * attributes[a].xyz + hit.b.x * attributes[a + 1u].xyz + hit.b.y * attributes[a + 2u].xyz;
        let len = length(n);
        if len > 0.0 {
            ns = n / len;
            ns = select(ns, -ns, dot(ns, ng) < 0.0);
        }
        a += 3u;
    }
    if USES_UVS && USES_TEXTURES && (tri.attributes & HAS_UVS) != 0u {
        let uv01 = attributes[a];
        uv = b0 * uv01.xy + hit.b.x * uv01.zw + hit.b.y * attributes[a + 1u].xy;
    }
    return Surface(p, ng, ns, tri.material, tri.shape, uv);
}

// The material of surface s, its albedo looked up in its texture when it has one: whatever
// the kind, a texture replaces albedo (a diffuse reflectance, a conductor's specular one).
fn material_at(s: Surface) -> Material {
    var m = materials[s.material];
    if USES_TEXTURES && m.texture != NO_TEXTURE {
        m.albedo = texture_value(m.texture, m.texture_size, s.uv);
    }
    return m;
}

// Texel index i wrapped into [0, n) by flags' wrap mode, as Mitsuba 3 (Dr.Jit's textures)
// does: repeat, mirror (period 2n, the edge texel repeated at each seam), clamp.
fn wrap_texel(i: i32, n: i32, flags: u32) -> i32 {
    if (flags & TEXTURE_CLAMP) != 0u {
        return clamp(i, 0, n - 1);
    }
    // The modulo of a negative integer is negative in WGSL.
    if (flags & TEXTURE_MIRROR) != 0u {
        let m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return select(m, 2 * n - 1 - m, m >= n);
    }
    return ((i % n) + n) % n;
}

// The texture with header `header` (see Material.texture; size: width | height << 16) at
// texture coordinates uv: (x, y) = to_uv * uv, x right and y down the image in [0, 1]^2, then
// bilinear between texel centres, which lie at half-integers of (x w, y h), or the texel
// (x w, y h) falls in (as Mitsuba 3's bitmap; a nearest lookup is the bilinear one at that
// texel's centre, with weights 0 and 1).
fn texture_value(header: u32, size_bits: u32, uv: vec2f) -> vec3f {
    let h0 = texels[header];
    let h1 = texels[header + 1u];
    let first = bitcast<u32>(h0.w);
    let flags = bitcast<u32>(h1.w);
    let size = vec2i(i32(size_bits & 0xffffu), i32(size_bits >> 16u));
    var p = vec2f(dot(h0.xy, uv) + h0.z, dot(h1.xy, uv) + h1.z) * vec2f(size);
    if (flags & TEXTURE_NEAREST) != 0u {
        p = floor(p) + 0.5;
    }
    p -= 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let i0 = vec2i(p0);
    let x0 = u32(wrap_texel(i0.x, size.x, flags));
    let x1 = u32(wrap_texel(i0.x + 1, size.x, flags));
    let row0 = first + u32(wrap_texel(i0.y, size.y, flags) * size.x);
    let row1 = first + u32(wrap_texel(i0.y + 1, size.y, flags) * size.x);
    let top = mix(texel(row0 + x0, first, flags), texel(row0 + x1, first, flags), f.x);
    let bottom = mix(texel(row1 + x0, first, flags), texel(row1 + x1, first, flags), f.x);
    return mix(top, bottom, f.y);
}

// Texel `first + i` of an image stored from `first`: as floats, or palette-coded (see
// TEXTURE_PALETTE: the palette's PALETTE_ENTRIES values, four a texel, then each texel's
// three 8-bit indices in one word, four words a texel).
fn texel(at: u32, first: u32, flags: u32) -> vec3f {
    if (flags & TEXTURE_PALETTE) == 0u {
        return texels[at].xyz;
    }
    let i = at - first;
    let word = bitcast<u32>(texels[first + PALETTE_ENTRIES / 4u + i / 4u][i % 4u]);
    let c = vec3u(word, word >> 8u, word >> 16u) & vec3u(0xffu);
    return vec3f(texels[first + c.x / 4u][c.x % 4u], texels[first + c.y / 4u][c.y % 4u], texels[first + c.z / 4u][c.z % 4u]);
}

// Offset a ray origin off the surface, to the side of `side` (pbrt-v4 sec. 6.8.6 in spirit:
// a fixed distance scaled to the scene, since positions here are single precision).
fn offset_origin(p: vec3f, ng: vec3f, side: vec3f) -> vec3f {
    let n = select(-ng, ng, dot(ng, side) >= 0.0);
    return p + frame.ray_epsilon * n;
}
