// Fresnel reflectance of smooth interfaces, shared by the BSDF families: a dielectric's
// (dielectric, thin_dielectric, plastic's coating) and a conductor's complex-index one.

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

// Fresnel reflectance of a conductor of complex index of refraction eta + i k for unpolarized
// light, per channel: pbrt-v4's FrComplex (eq. 9.6 with a complex eta) in real arithmetic. With
// t = eta^2 - k^2 - sin^2, a^2 + b^2 = sqrt(t^2 + 4 eta^2 k^2) and a^2 = (a^2 + b^2 + t) / 2,
//   R_s = (a^2 + b^2 + cos^2 - 2 a cos) / (a^2 + b^2 + cos^2 + 2 a cos),
//   R_p = R_s ((a^2 + b^2) cos^2 + sin^4 - 2 a cos sin^2) / ((a^2 + b^2) cos^2 + sin^4 + 2 a cos sin^2)
// (Born and Wolf, "Principles of Optics", sec. 14.2), and F = (R_s + R_p) / 2. eta 0, k 1 gives
// exactly 1.
fn fresnel_conductor(cos_i_in: f32, eta: vec3f, k: vec3f) -> vec3f {
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let cos2 = cos_i * cos_i;
    let sin2 = 1.0 - cos2;
    let t = eta * eta - k * k - vec3f(sin2);
    let a2_b2 = sqrt(max(vec3f(0.0), t * t + 4.0 * eta * eta * k * k));
    let a = sqrt(max(vec3f(0.0), 0.5 * (a2_b2 + t)));
    let s_sum = a2_b2 + vec3f(cos2);
    let s_diff = 2.0 * cos_i * a;
    let r_s = (s_sum - s_diff) / max(s_sum + s_diff, vec3f(1e-30));
    let p_sum = a2_b2 * cos2 + vec3f(sin2 * sin2);
    let p_diff = s_diff * sin2;
    let r_p = r_s * (p_sum - p_diff) / max(p_sum + p_diff, vec3f(1e-30));
    return 0.5 * (r_s + r_p);
}
