// pathtrace_scatter.glsl: local events of the volumetric path tracers (thesis 3.2,
// Algorithm 1): Henyey-Greenstein phase sampling, direction frames and the unpolarised
// dielectric Fresnel reflectance. Pure functions; no #version, no uniforms.

const float PT_PI = 3.14159265358979323846;

// cos θ of a Henyey-Greenstein deflection by exact inversion of its CDF. The textbook form
//   cos θ = (1 + g² − ((1 − g²)/(1 − g + 2gξ))²) / (2g)
// cancels catastrophically in float for small |g| and divides by zero at g = 0; multiplied
// out with u = 1 − 2ξ and d = 1 − g·u it is the same function without the 1/g:
//   cos θ = (−u + ½g(3 + u² − 2gu + g²(u² − 1))) / d²
// which is exactly 2ξ − 1 (isotropic) at g = 0.
float sampleHgCos(float g, float xi) {
    float u = 1.0 - 2.0 * xi;
    float d = 1.0 - g * u;
    float num = -u + 0.5 * g * (3.0 + u * u - 2.0 * g * u + g * g * (u * u - 1.0));
    return clamp(num / (d * d), -1.0, 1.0);
}

// Unit direction at angle θ (cos θ given) and azimuth φ about the unit vector d. The frame is
// Duff et al., "Building an orthonormal basis, revisited" (JCGT 2017), branch-free and stable
// for every d; the result is renormalised so float rounding cannot accumulate over a path.
vec3 deflect(vec3 d, float cosT, float phi) {
    float sinT = sqrt(max(0.0, 1.0 - cosT * cosT));
    float sgn = d.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sgn + d.z);
    float b = d.x * d.y * a;
    vec3 t = vec3(1.0 + sgn * d.x * d.x * a, sgn * b, -sgn * d.x);
    vec3 bt = vec3(b, sgn + d.y * d.y * a, -d.y);
    return normalize(sinT * cos(phi) * t + sinT * sin(phi) * bt + cosT * d);
}

// Fresnel reflectance for unpolarised light arriving from inside a medium of relative index
// eta (medium / outside) at a plane boundary, cosI = cosine to the normal (> 0). Exact
// (average of the s and p reflectances); 1 under total internal reflection; 0 when eta = 1.
float fresnelExit(float cosI, float eta) {
    if (eta == 1.0) return 0.0;
    float sinT2 = eta * eta * max(0.0, 1.0 - cosI * cosI);
    if (sinT2 >= 1.0) return 1.0;
    float cosT = sqrt(1.0 - sinT2);
    float rs = (eta * cosI - cosT) / (eta * cosI + cosT);
    float rp = (eta * cosT - cosI) / (eta * cosT + cosI);
    return 0.5 * (rs * rs + rp * rp);
}
