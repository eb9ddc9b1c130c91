// Scattering at specular surfaces, shared by camera paths and photon paths.

// Fresnel reflectance of a dielectric for unpolarized light (pbrt-v4 eq. 9.6); eta is the
// ratio of the transmitted side's index to the incident side's.
fn fresnel_dielectric(cos_i_in: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (r_parl * r_parl + r_perp * r_perp);
}

struct SpecularSample {
    wi: vec3f,
    // Throughput factor f * |cos| / pdf.
    weight: vec3f,
}

// Sample a smooth dielectric from direction of travel d at normal ng. Reflection or
// refraction is chosen with the Fresnel probability, so the weight is 1, times 1 / eta^2 for
// refracted radiance (pbrt-v4 sec. 9.5.2); photons carry flux and are not scaled.
fn sample_dielectric(d: vec3f, ng: vec3f, ior: f32, u: f32, radiance: bool) -> SpecularSample {
    let entering = dot(d, ng) < 0.0;
    let n = select(-ng, ng, entering);
    let eta = select(1.0 / ior, ior, entering);
    let cos_i = -dot(d, n);
    let f = fresnel_dielectric(cos_i, eta);
    if u < f {
        return SpecularSample(reflect(d, n), vec3f(1.0));
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    let wt = normalize(d / eta + (cos_i / eta - cos_t) * n);
    let scale = select(1.0, 1.0 / (eta * eta), radiance);
    return SpecularSample(wt, vec3f(scale));
}
