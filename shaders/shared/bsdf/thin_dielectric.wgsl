// Thin dielectric slabs (MATERIAL_THIN_DIELECTRIC; Mitsuba 3's `thindielectric`, and its
// `null`, drawn as a slab of index 1): a pane too thin to see. It reflects about ns with the
// slab's summed reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R), R = F(|cos|) at its
// index (thindielectric.cpp), and passes the rest straight through, unbent: both lobes are
// deltas, for flux and radiance alike.
// Parameters: `ior` of the slab relative to the outside (1: Mitsuba's null, which reflects
// nothing); `specular` and `transmittance` scale the reflection and the transmission.
// Two-sided by nature.

#import types
#import scene
#import bsdf/lobe
#import bsdf/fresnel

const MATERIAL_THIN_DIELECTRIC: u32 = 5u;

// Some material is a thin dielectric or null (src/scene/material/thin_dielectric.rs).
override USES_THIN_DIELECTRIC: bool = true;

// Sample thin dielectric m (Mitsuba 3's thindielectric) from direction of travel d at s:
// reflect about ns with the slab's summed reflectance R' = R + T^2 R / (1 - R^2) = 2R / (1 + R),
// R = F(|cos|) at its index (thindielectric.cpp), else pass straight through, unbent. The
// branch is chosen with its probability, so the weights are the tints; flux and radiance alike,
// since nothing refracts. A reflection about ns that crosses ng ends the path.
fn thin_dielectric_sample(m: Material, albedo: vec3f, d: vec3f, s: Surface, u: vec3f, radiance: bool) -> BsdfSample {
    // Index 1 (Mitsuba's null BSDF) reflects nothing; exactly, not by Fresnel's roundoff.
    let r = select(fresnel_dielectric(abs(dot(d, s.ns)), m.ior), 0.0, m.ior == 1.0);
    if u.z < 2.0 * r / (1.0 + r) {
        let n = select(-s.ns, s.ns, dot(d, s.ns) < 0.0);
        let wi = reflect(d, n);
        let weight = select(vec3f(0.0), m.specular, dot(wi, s.ng) * dot(d, s.ng) < 0.0);
        return bsdf_specular(wi, weight);
    }
    return bsdf_specular(d, m.transmittance);
}

// Whether m is Mitsuba's null (as the host packs it: a slab of index 1 passing everything):
// an invisible boundary that shadow rays in media cross (shared/direct.wgsl).
fn is_null(m: Material) -> bool {
    return USES_THIN_DIELECTRIC && m.kind == MATERIAL_THIN_DIELECTRIC && m.ior == 1.0 && all(m.transmittance == vec3f(1.0))
        && all(m.specular == vec3f(0.0));
}
