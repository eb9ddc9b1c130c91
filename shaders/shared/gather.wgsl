// A photon's acceptance at a visible point: the one set of tests by which photon_gather adds
// the stored hits and photon_pass's deposit_at a direct deposit.

#import types
#import sampling
#import grid

// A visible point as the tests read it, unpacked once (photon_gather tests many photons
// against one point).
struct Gatherer {
    p: vec3f,
    radius: f32,
    // The point's normal as decode_normal returns it, and of unit length.
    n: vec3f,
    n_unit: vec3f,
    // Scattering events of its camera path.
    depth: u32,
    // In a participating medium.
    volume: bool,
}

fn gatherer(q: VisiblePoint) -> Gatherer {
    let n = decode_normal(q.normal);
    return Gatherer(q.p, q.radius, n, normalize(n), vp_depth(q.normal), in_volume(q.normal));
}

// Whether a photon at x, arriving along d after `depth` scattering events, adds to point g:
// within its radius, the joined path not longer than max_depth, and a point in a medium
// gathers the photons in media, one on a surface those on surfaces, from its side
// (lights_side, same_side in shared/grid.wgsl). `normal` is encode_normal's, of the surface
// the photon hit turned to the side it arrived from (volume_normal's in a medium).
fn accepts(g: Gatherer, x: vec3f, d: vec3f, depth: u32, normal: u32, max_depth: u32) -> bool {
    if !within_radius(g.p, g.radius, x) || !within_depth(g.depth, depth, max_depth) {
        return false;
    }
    if USES_MEDIA && g.volume != in_volume(normal) {
        return false;
    }
    return g.volume || (lights_side(g.n, d) && same_side(g.n_unit, decode_normal(normal), x - g.p));
}
