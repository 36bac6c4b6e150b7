// bssrdf/oblique_table: oblique path-traced tables as a model's generated shader (see
// oblique_table.h for the conversion and the interpolation).
#include "bssrdf/oblique_table.h"

#include "bssrdf/detail/text_lines.h"
#include "core/core.h"
#include "core/text.h"
#include "pathtrace/fresnel.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

namespace bssrdf {
namespace {

constexpr int kQuadratureSteps = 4096; // midpoint steps per ring

// ∫_{mu0}^{mu1} T(μ) μ dμ by the midpoint rule.
double transmittanceMoment(double eta, double mu0, double mu1) {
    const double h = (mu1 - mu0) / kQuadratureSteps;
    double sum = 0;
    for (int k = 0; k < kQuadratureSteps; ++k) {
        const double mu = mu0 + (k + 0.5) * h;
        sum += (1.0 - pathtrace::fresnelDielectric(mu, eta)) * mu;
    }
    return sum * h;
}

std::string angleList(const std::vector<double>& a) {
    std::string s;
    for (size_t i = 0; i < a.size(); ++i)
        s += (i ? "," : "") + core::formatNumber(a[i]);
    return s;
}

bool sameBins(const pathtrace::BssrdfBins& a, const pathtrace::BssrdfBins& b) {
    return a.rEdges() == b.rEdges() && a.thetaSBins == b.thetaSBins &&
           a.dirCosBins == b.dirCosBins && a.dirPhiBins == b.dirPhiBins;
}

} // namespace

bool isRadialTable(const pathtrace::BssrdfTable& t) {
    const auto& s = t.settings;
    return s.thetaIDeg == std::vector<double>{0.0} && s.bins.thetaSBins == 1 &&
           s.bins.dirBins() == 1;
}

double diffuseTransmittance(double eta) {
    return 2.0 * transmittanceMoment(eta, 0.0, 1.0);
}

double ringTransmittance(double eta, int ring, int rings) {
    const double mu0 = double(ring) / rings, mu1 = double(ring + 1) / rings;
    return transmittanceMoment(eta, mu0, mu1) / (0.5 * (mu1 * mu1 - mu0 * mu0));
}

ObliqueTable obliqueTable(const std::vector<pathtrace::BssrdfTable>& tables,
                          const std::vector<std::string>& names) {
    const pathtrace::BssrdfTable& t0 = tables.at(0);
    const auto& b = t0.settings.bins;
    const auto& th = t0.settings.thetaIDeg;
    for (size_t i = 0; i < th.size(); ++i)
        if (i > 0 && !(th[i] > th[i - 1]))
            throw core::Error(names[0], 0,
                              "its incidence angles (theta_i " + angleList(th) +
                                  ") must increase strictly: estimate again with the angles in "
                                  "increasing order, each once");
    for (size_t i = 1; i < tables.size(); ++i) {
        const auto& ti = tables[i];
        if (!sameBins(ti.settings.bins, b))
            throw core::Error(names[i], 0,
                              "its bins (r, theta_s or direction cells) differ from " + names[0] +
                                  "'s: the channels of a table model share one grid");
        if (ti.settings.thetaIDeg != th)
            throw core::Error(names[i], 0,
                              "has theta_i " + angleList(ti.settings.thetaIDeg) + " but " +
                                  names[0] + " has " + angleList(th) +
                                  ": the channels of a table model need the same incidence angles");
        if (ti.medium.eta != t0.medium.eta)
            throw core::Error(names[i], 0,
                              "its eta " + core::formatNumber(ti.medium.eta) + " differs from " +
                                  names[0] + "'s " + core::formatNumber(t0.medium.eta) +
                                  ": a material has one index of refraction");
    }
    ObliqueTable o;
    o.thetaIDeg = th;
    const auto edges = b.rEdges();
    for (size_t k = 0; k + 1 < edges.size(); ++k)
        o.r.push_back(0.5 * (edges[k] + edges[k + 1]));
    o.thetaSBins = b.thetaSBins;
    o.dirCosBins = b.dirCosBins;
    o.dirPhiBins = b.dirPhiBins;
    const size_t nR = o.r.size(), nS = size_t(o.thetaSBins), nC = size_t(o.cells());
    const size_t entries = th.size() * nR * nS * nC;
    if (entries > kMaxObliqueValues / 3)
        throw core::Error(names[0], 0,
                          "too large for a table model: " + std::to_string(th.size()) +
                              " angles x " + std::to_string(nR) + " radii x " + std::to_string(nS) +
                              " theta_s bins x " + std::to_string(nC) +
                              " direction cells x 3 = " + std::to_string(3 * entries) +
                              " values, at most " + std::to_string(kMaxObliqueValues) +
                              ": estimate a smaller table (fewer r, theta_s or direction bins, "
                              "fewer angles)");
    const double eta = t0.medium.eta;
    const double diffuse = diffuseTransmittance(eta);
    std::vector<double> ringRatio(size_t(o.dirCosBins));
    for (int ring = 0; ring < o.dirCosBins; ++ring) {
        const double tr = nC == 1 ? diffuse : ringTransmittance(eta, ring, o.dirCosBins);
        ringRatio[size_t(ring)] = tr > 0 ? diffuse / tr : 0.0;
    }
    o.value.assign(entries, {0.0, 0.0, 0.0});
    for (int c = 0; c < 3; ++c) {
        const size_t i = tables.size() == 1 ? 0 : size_t(c);
        for (size_t a = 0; a < th.size(); ++a) {
            const pathtrace::BssrdfSlice s = tables[i].slice(a);
            if (s.paths == 0)
                throw core::Error(names[i], 0,
                                  "theta_i " + core::formatNumber(th[a]) +
                                      ": no paths traced (an empty shard?)");
            const double entering = 1.0 - s.specular;
            for (size_t ir = 0; ir < nR; ++ir)
                for (size_t is = 0; is < nS; ++is)
                    for (size_t ic = 0; ic < nC; ++ic) {
                        const size_t bin = ir * nS + is;
                        // One cell: S = R/π, so π·S is R itself (no rounding).
                        const double piS =
                            nC == 1 ? s.R[bin] : std::numbers::pi * s.S[bin * nC + ic];
                        const double v = piS * ringRatio[ic / size_t(o.dirPhiBins)] / entering;
                        if (!std::isfinite(v) || v < 0)
                            throw core::Error(
                                names[i], 0,
                                "theta_i " + core::formatNumber(th[a]) + ", r bin " +
                                    std::to_string(ir) + ", theta_s bin " + std::to_string(is) +
                                    ", cell " + std::to_string(ic) + ": the value " +
                                    core::formatNumber(v) + " is not finite and >= 0");
                        o.value[o.index(a, ir, is, ic)][size_t(c)] = v;
                    }
        }
    }
    return o;
}

std::string obliqueTableGlsl(const ObliqueTable& t) {
    const size_t nA = t.thetaIDeg.size(), nR = t.r.size();
    std::ostringstream g;
    g << "// generated from the table section: oblique table, " << nA << " incidence angles, " << nR
      << " radii, " << t.thetaSBins << " theta_s bins, " << t.dirCosBins << "x" << t.dirPhiBins
      << " direction cells (bssrdf/oblique_table.h)\n";
    g << "const int TabA = " << nA << ";\nconst int TabR = " << nR
      << ";\nconst int TabS = " << t.thetaSBins << ";\nconst int TabCos = " << t.dirCosBins
      << ";\nconst int TabPhi = " << t.dirPhiBins << ";\nconst int TabCells = " << t.cells()
      << ";\n";
    g << "const float TabThetaI[" << nA << "] = float[](";
    for (size_t i = 0; i < nA; ++i)
        g << (i ? ", " : "") << detail::glslFloat(t.thetaIDeg[i] * std::numbers::pi / 180.0);
    g << ");\nconst float TabRad[" << nR << "] = float[](";
    for (size_t i = 0; i < nR; ++i)
        g << (i ? ", " : "") << detail::glslFloat(t.r[i]);
    g << ");\nconst vec3 TabV[" << t.value.size() << "] = vec3[](";
    for (size_t i = 0; i < t.value.size(); ++i)
        g << (i ? ",\n" : "") << "vec3(" << detail::glslFloat(t.value[i][0]) << ", "
          << detail::glslFloat(t.value[i][1]) << ", " << detail::glslFloat(t.value[i][2]) << ")";
    g << ");\n";
    g << R"GLSL(
// Value at angle index a, radii r0/r1 (weight fr), θs bins s0/s1 (weight fs), cell c.
vec3 tabSlice(int a, int r0, int r1, float fr, int s0, int s1, float fs, int c) {
    int b0 = (a * TabR + r0) * TabS, b1 = (a * TabR + r1) * TabS;
    vec3 lo = mix(TabV[(b0 + s0) * TabCells + c], TabV[(b0 + s1) * TabCells + c], fs);
    vec3 hi = mix(TabV[(b1 + s0) * TabCells + c], TabV[(b1 + s1) * TabCells + c], fs);
    return mix(lo, hi, fr);
}

// The cell of an exit direction with cos θo = cosO and azimuth phi (radians) in the beam frame.
int tabCell(float cosO, float phi) {
    int ring = clamp(int(cosO * float(TabCos)), 0, TabCos - 1);
    float p = phi < 0.0 ? phi + 2.0 * PI : phi;
    int sector = clamp(int(p * (float(TabPhi) / (2.0 * PI))), 0, TabPhi - 1);
    return ring * TabPhi + sector;
}

float tabAtan(float y, float x) {
    return (x == 0.0 && y == 0.0) ? 0.0 : atan(y, x);
}

// Value between angles a0/a1 (weight fa), radii r0/r1 (fr), θs bins s0/s1 (fs) for the exit
// direction: its cell, or without an exit azimuth (Wo along the normal) the mean over the
// sectors of its ring.
vec3 tabExit(int a0, int a1, float fa, int r0, int r1, float fr, int s0, int s1, float fs,
             float cosO, bool hasAzimuth, float phi) {
    if (hasAzimuth) {
        int c = tabCell(cosO, phi);
        return mix(tabSlice(a0, r0, r1, fr, s0, s1, fs, c), tabSlice(a1, r0, r1, fr, s0, s1, fs, c),
                   fa);
    }
    int first = clamp(int(cosO * float(TabCos)), 0, TabCos - 1) * TabPhi;
    vec3 sum = vec3(0.0);
    for (int k = 0; k < TabPhi; ++k)
        sum += mix(tabSlice(a0, r0, r1, fr, s0, s1, fs, first + k),
                   tabSlice(a1, r0, r1, fr, s0, s1, fs, first + k), fa);
    return sum / float(TabPhi);
}

vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {
    vec3 d = Xo - Xi;
    float r = length(d);
    if (!(r < TabRad[TabR - 1])) return vec3(0.0);
    int r0 = 0, r1 = 0;
    float fr = 0.0;
    if (r > TabRad[0]) {
        int lo = 0, hi = TabR - 1;
        while (hi - lo > 1) {
            int mid = (lo + hi) / 2;
            if (TabRad[mid] <= r) lo = mid; else hi = mid;
        }
        r0 = lo;
        r1 = hi;
        fr = (r - TabRad[lo]) / (TabRad[hi] - TabRad[lo]);
    }
    float tangential = length(Wi.xy);
    float thetaI = Wi.z > 0.0 ? atan(tangential, Wi.z) : 0.5 * PI; // below the surface: 90°
    int a0 = TabA - 1, a1 = TabA - 1;
    float fa = 0.0;
    if (!(thetaI >= TabThetaI[TabA - 1])) {
        a0 = 0;
        a1 = 0;
        for (int k = 1; k < TabA; ++k) {
            if (thetaI > TabThetaI[k - 1] && thetaI < TabThetaI[k]) {
                a0 = k - 1;
                a1 = k;
                fa = (thetaI - TabThetaI[k - 1]) / (TabThetaI[k] - TabThetaI[k - 1]);
            } else if (thetaI == TabThetaI[k]) {
                a0 = k;
                a1 = k;
            }
        }
    }
    float cosO = clamp(Wo.z, 0.0, 1.0);
    bool hasAzimuth = length(Wo.xy) >= 1e-6;
    float sector = PI / float(TabS);
    if (tangential < 1e-6) {
        // Normal incidence: the mean over the θs bins, the exit azimuth measured from each
        // bin's beam axis (the in-plane direction of Xo − Xi turned back by the bin's centre).
        float phiRel = tabAtan(Wo.y, Wo.x) - tabAtan(d.y, d.x);
        vec3 sum = vec3(0.0);
        for (int k = 0; k < TabS; ++k)
            sum += tabExit(a0, a1, fa, r0, r1, fr, k, k, 0.0, cosO, hasAzimuth,
                           mod(phiRel + (float(k) + 0.5) * sector, 2.0 * PI));
        return sum / float(TabS);
    }
    vec2 beam = -Wi.xy / tangential;
    vec2 side = vec2(-beam.y, beam.x);
    float px = dot(d.xy, beam), py = dot(d.xy, side);
    float mirror = py < 0.0 ? -1.0 : 1.0;
    float u = tabAtan(abs(py), px) / sector - 0.5;
    float fl = floor(u);
    int s0 = clamp(int(fl), 0, TabS - 1), s1 = clamp(int(fl) + 1, 0, TabS - 1);
    float fs = clamp(u - fl, 0.0, 1.0);
    return tabExit(a0, a1, fa, r0, r1, fr, s0, s1, fs, cosO, hasAzimuth,
                   tabAtan(mirror * dot(Wo.xy, side), dot(Wo.xy, beam)));
}
)GLSL";
    return g.str();
}

} // namespace bssrdf
