// Irradiance stage shared code (modules/irradiance): the point layout and the Fresnel
// transmittance Ft = 1 − R of light entering from index 1 into relative index eta (exact
// unpolarised Fresnel equations, as pathtrace/fresnel.h):
//   sin²θt = (1 − cos²θi)/eta², rs = (cos θi − eta cos θt)/(cos θi + eta cos θt),
//   rp = (eta cos θi − cos θt)/(eta cos θi + cos θt), R = (rs² + rp²)/2;
// 0 for cos θi <= 0 and under total internal reflection (only possible for eta < 1).
struct IrradiancePoint {
    vec4 position; // xyz, w unused
    vec4 normal;   // xyz unit, w unused
};

float irradianceFt(float cosI, float eta) {
    if (cosI <= 0.0) return 0.0;
    float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 0.0;
    float cosT = sqrt(1.0 - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}
