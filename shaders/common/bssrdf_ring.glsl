// bssrdf_ring.glsl: the azimuth of a connection point on a ring of the surface, sampled
// proportionally to 1/d² from a vertex below it, by the wrapped Cauchy distribution (Mardia &
// Jupp 2000, §3.5.7) — the GPU form of modules/pathtrace/detail/ring_sampler.h; no #version.
//   A vertex at horizontal distance ρ (azimuth μ) and depth z sees the ring point at radius r
//   and azimuth θ at squared distance d² = A − B cos(θ − μ), A = r² + ρ² + z², B = 2rρ. The
//   density (1 − c²) / (2π (1 + c² − 2c cos Δ)) is ∝ 1/d² for c = B / (A + sqrt(A² − B²)).
// In float every difference of nearly equal numbers is formed without cancellation:
//   A − B = (r − ρ)² + z²,  1 − c = (A − B + S)/(A + S) with S = sqrt((A − B)(A + B)),
//   1 + c² − 2c cos Δ = (1 − c)² + 2c (1 − cos Δ),  1 − cos Δ = |e_θ − e_μ|²/2,
// and the inverse CDF tan(Δ/2) = tan(π(ξ − ½))/k, k = (1 + c)/(1 − c), is evaluated as
// ∓1/(k tan(π min(ξ, 1 − ξ))), accurate in the tails where tan(π(ξ − ½)) is not.
// Needs PT_PI (common/pathtrace_scatter.glsl).

struct Ring {
    vec2 mu;   // unit vector toward the vertex's azimuth ((1, 0) on the axis)
    float c;   // wrapped Cauchy concentration, [0, 1)
    float omc; // 1 − c
};

Ring ringSetup(vec2 vertex, float z, float r) {
    float rho = length(vertex);
    float a = r * r + rho * rho + z * z;
    float b = 2.0 * r * rho;
    float amb = (r - rho) * (r - rho) + z * z;
    float s = sqrt(amb * (a + b));
    Ring g;
    g.mu = rho > 0.0 ? vertex / rho : vec2(1.0, 0.0);
    g.c = b / (a + s);
    g.omc = (amb + s) / (a + s);
    return g;
}

// Density of θ on the circle (∫ over 2π = 1) given 1 − cos Δ.
float ringDensity(Ring g, float oneMinusCos) {
    return g.omc * (1.0 + g.c) /
           (2.0 * PT_PI * (g.omc * g.omc + 2.0 * g.c * oneMinusCos));
}

// Density at the unit vector e = (cos θ, sin θ).
float ringPdf(Ring g, vec2 e) {
    vec2 diff = e - g.mu;
    return ringDensity(g, 0.5 * dot(diff, diff));
}

// A point e = (cos θ, sin θ) of the ring for xi in (0, 1); returns its density.
float ringSample(Ring g, float xi, out vec2 e) {
    float k = (1.0 + g.c) / g.omc;
    float t = (xi < 0.5 ? -1.0 : 1.0) / (k * tan(PT_PI * min(xi, 1.0 - xi)));
    float inv = 1.0 / (1.0 + t * t);
    float cd = (1.0 - t * t) * inv, sd = 2.0 * t * inv;
    e = vec2(cd * g.mu.x - sd * g.mu.y, sd * g.mu.x + cd * g.mu.y);
    return ringDensity(g, 2.0 * t * t * inv);
}
