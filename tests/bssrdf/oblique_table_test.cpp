// Oblique table models (bssrdf/oblique_table.h): a `.bwtable` with several θs bins, direction
// cells and incidence angles as a non-radial model. Checked on real GL (render_pairs.comp):
// the generated Bssrdf() against an independent double evaluation of the conversion
// Bssrdf = π(1 − F_dr,ext)·S_cell/((1 − R_sp(θi))·T̄_cell) and of the interpolation (exact at
// bin centres, linear between, clamped θi, normal incidence as the θs mean), the mirror
// symmetry y → −y, the attributes, and bad inputs (channels with other bins, angles or η,
// unsorted or repeated angles, negative sums, angles without paths, too many values).
#include "../support/gl_fixture.h"
#include "bssrdf/oblique_table.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "bssrdf/sphere_integrator.h"
#include "core/core.h"
#include "mesh/mesh.h"
#include "octree/octree.h"
#include "pathtrace/bssrdf_table.h"
#include "pathtrace/fresnel.h"
#include "pointcloud/pointcloud.h"
#include "render/frame_analysis.h"
#include "render/render.h"
#include "shader/program.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace {
namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

const pathtrace::Medium kMedium{0.1, 1.0, 0.0, 1.3};

pathtrace::EstimateSettings obliqueSettings() {
    pathtrace::EstimateSettings s;
    s.thetaIDeg = {0.0, 60.0};
    s.bins.rBins = 4;
    s.bins.rMaxMm = 2;
    s.bins.thetaSBins = 3;
    s.bins.dirCosBins = 2;
    s.bins.dirPhiBins = 4;
    s.paths = 16384;
    return s;
}

const pathtrace::BssrdfTable& obliqueTableData() {
    static const pathtrace::BssrdfTable t = [] {
        const auto s = obliqueSettings();
        return pathtrace::estimateTable(kMedium, s, 0, pathtrace::chunkCount(s));
    }();
    return t;
}

// Independent double evaluation of a one-table model (all channels alike).
struct Reference {
    const pathtrace::BssrdfTable& t;
    std::vector<pathtrace::BssrdfSlice> slices;
    std::vector<double> centres, ringFactor;

    explicit Reference(const pathtrace::BssrdfTable& table) : t(table) {
        for (size_t a = 0; a < t.settings.thetaIDeg.size(); ++a)
            slices.push_back(t.slice(a));
        const auto e = t.settings.bins.rEdges();
        for (size_t k = 0; k + 1 < e.size(); ++k)
            centres.push_back(0.5 * (e[k] + e[k + 1]));
        // Simpson's rule on T(μ)·μ (the module uses a midpoint rule).
        auto moment = [&](double mu0, double mu1) {
            const int n = 20000;
            const double h = (mu1 - mu0) / n;
            double s = 0;
            for (int k = 0; k <= n; ++k) {
                const double mu = mu0 + k * h;
                const double f =
                    mu > 0 ? (1 - pathtrace::fresnelDielectric(mu, t.medium.eta)) * mu : 0.0;
                s += f * (k == 0 || k == n ? 1 : (k % 2 ? 4 : 2));
            }
            return s * h / 3;
        };
        const int rings = t.settings.bins.dirCosBins;
        const double diffuse = 2 * moment(0, 1);
        for (int q = 0; q < rings; ++q) {
            const double mu0 = double(q) / rings, mu1 = double(q + 1) / rings;
            ringFactor.push_back(diffuse / (moment(mu0, mu1) / (0.5 * (mu1 * mu1 - mu0 * mu0))));
        }
    }
    int nS() const { return t.settings.bins.thetaSBins; }
    int nC() const { return t.settings.bins.dirBins(); }
    // The converted table value of (angle, radius, θs bin, cell).
    double at(size_t a, size_t ir, size_t is, size_t c) const {
        const auto& s = slices[a];
        const size_t bin = ir * size_t(nS()) + is;
        const double S = nC() == 1 ? s.R[bin] / kPi : s.S[bin * size_t(nC()) + c];
        return kPi * S * ringFactor[c / size_t(t.settings.bins.dirPhiBins)] / (1 - s.specular);
    }
    int cell(double cosO, double phi) const {
        const auto& b = t.settings.bins;
        if (phi < 0) phi += 2 * kPi;
        const int ring = std::clamp(int(cosO * b.dirCosBins), 0, b.dirCosBins - 1);
        const int sector = std::clamp(int(phi / (2 * kPi) * b.dirPhiBins), 0, b.dirPhiBins - 1);
        return ring * b.dirPhiBins + sector;
    }
    // Linear weights between bracketing nodes (clamped at the ends).
    static void bracket(const std::vector<double>& x, double v, size_t& i0, size_t& i1, double& f) {
        i0 = i1 = 0;
        f = 0;
        if (v <= x.front()) return;
        if (v >= x.back()) {
            i0 = i1 = x.size() - 1;
            return;
        }
        while (!(v >= x[i0] && v < x[i0 + 1]))
            ++i0;
        i1 = i0 + 1;
        f = (v - x[i0]) / (x[i1] - x[i0]);
    }
    // Value at angle θi (deg), radius r, θs (rad, in [0, π]) and cell c.
    double value(double thetaIDeg, double r, double thetaS, int c) const {
        if (r >= centres.back()) return 0;
        size_t r0, r1, a0, a1, s0, s1;
        double fr, fa, fs;
        bracket(centres, r, r0, r1, fr);
        bracket(t.settings.thetaIDeg, thetaIDeg, a0, a1, fa);
        std::vector<double> sc;
        for (int k = 0; k < nS(); ++k)
            sc.push_back((k + 0.5) * kPi / nS());
        bracket(sc, thetaS, s0, s1, fs);
        auto slice = [&](size_t a) {
            auto lerpS = [&](size_t ir) {
                return (1 - fs) * at(a, ir, s0, size_t(c)) + fs * at(a, ir, s1, size_t(c));
            };
            return (1 - fr) * lerpS(r0) + fr * lerpS(r1);
        };
        return (1 - fa) * slice(a0) + fa * slice(a1);
    }
    // f(cell) at the exit direction's cell, or with no exit azimuth (wo along the normal) the
    // mean over the sectors of its ring.
    template <class F> double exitValue(const F& f, glm::dvec3 wo, double phi) const {
        const double cosO = std::clamp(wo.z, 0.0, 1.0);
        if (std::hypot(wo.x, wo.y) >= 1e-6) return f(cell(cosO, phi));
        const int nPhi = t.settings.bins.dirPhiBins;
        const int first = cell(cosO, 0.0);
        double sum = 0;
        for (int k = 0; k < nPhi; ++k)
            sum += f(first + k);
        return sum / nPhi;
    }
    // The model at normal incidence (Wi = +z): the θs mean, exit azimuth from each bin's axis.
    double evalNormal(glm::dvec3 xi, glm::dvec3 xo, glm::dvec3 wo) const {
        const glm::dvec3 d = xo - xi;
        const double r = glm::length(d);
        if (r >= centres.back()) return 0;
        size_t r0, r1;
        double fr;
        bracket(centres, r, r0, r1, fr);
        auto atan2z = [](double y, double x) { return x == 0 && y == 0 ? 0.0 : std::atan2(y, x); };
        const double phiRel = atan2z(wo.y, wo.x) - atan2z(d.y, d.x);
        double sum = 0;
        for (int k = 0; k < nS(); ++k) {
            auto f = [&](int c) {
                return (1 - fr) * at(0, r0, size_t(k), size_t(c)) +
                       fr * at(0, r1, size_t(k), size_t(c));
            };
            sum += exitValue(f, wo, std::fmod(phiRel + (k + 0.5) * kPi / nS() + 4 * kPi, 2 * kPi));
        }
        return sum / nS();
    }
    // The model at (Xi, Wi, Xo, Wo) with a beam (Wi not along the normal).
    double eval(glm::dvec3 xi, glm::dvec3 wi, glm::dvec3 xo, glm::dvec3 wo) const {
        const glm::dvec3 d = xo - xi;
        const double tan = std::hypot(wi.x, wi.y);
        const double thetaI = std::atan2(tan, std::max(wi.z, 0.0)) * 180 / kPi;
        const glm::dvec2 beam = -glm::dvec2(wi.x, wi.y) / tan, side(-beam.y, beam.x);
        const double px = glm::dot(glm::dvec2(d), beam), py = glm::dot(glm::dvec2(d), side);
        const double mirror = py < 0 ? -1 : 1;
        const double phi =
            std::atan2(mirror * glm::dot(glm::dvec2(wo), side), glm::dot(glm::dvec2(wo), beam));
        return exitValue(
            [&](int c) { return value(thetaI, glm::length(d), std::atan2(std::fabs(py), px), c); },
            wo, phi);
    }
};

glm::dvec3 direction(double cosTheta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    return {s * std::cos(phi), s * std::sin(phi), cosTheta};
}

class ObliqueTable : public ::testing::Test {
  protected:
    void SetUp() override {
        m_root = testsupport::makeProjectRoot("obliquetable", {});
        m_dir = m_root / "materials";
    }
    void TearDown() override { fs::remove_all(m_root); }
    void write(const std::string& name, const std::string& text) {
        std::ofstream(m_dir / name, std::ios::binary) << text;
    }
    void model(const std::string& name, const std::string& directive) {
        write(name + ".bssrdf",
              "analytic radial no_wi no_wo\n::begin table\n" + directive + "\n::end table\n");
    }
    bssrdf::Model load(const std::string& name) {
        return bssrdf::loadModel(m_dir / (name + ".bssrdf"), "materials/" + name + ".bssrdf");
    }
    void expectError(const std::string& name, const std::vector<std::string>& fragments) {
        try {
            load(name);
            ADD_FAILURE() << name << " loaded";
        } catch (const core::Error& e) {
            for (const auto& f : fragments)
                EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
                    << "'" << f << "' not in: " << e.what();
        }
    }
    // Bssrdf() of model `name` on the GPU for every pair.
    std::vector<glm::vec3> evaluate(const std::string& name,
                                    const std::vector<render::BssrdfPair>& pairs) {
        bssrdf::ModelLibrary lib(m_root, {"render_pairs.comp"});
        lib.scanAll();
        const bssrdf::ModelEntry* e = lib.find(name);
        EXPECT_NE(e, nullptr);
        if (!e || !e->model || !e->programs.count("render_pairs.comp")) {
            ADD_FAILURE() << name << " unusable: " << (e && e->problem ? e->problem->text() : "");
            return {};
        }
        bssrdf::Builtins b;
        b.sigmaA = glm::vec3(float(kMedium.sigmaA));
        b.sigmaS = glm::vec3(float(kMedium.sigmaS));
        b.ior = float(kMedium.eta);
        return render::evaluatePairs(e->programs.at("render_pairs.comp").id(), *e->model, e->values,
                                     b, pairs);
    }
    fs::path m_root, m_dir;
};

render::BssrdfPair pair(glm::dvec3 xi, glm::dvec3 wi, glm::dvec3 xo, glm::dvec3 wo) {
    return {glm::vec3(xi), glm::vec3(wi), glm::vec3(xo), glm::vec3(wo)};
}

// (a) At bin centres the model is the converted table value; between them it is the
// interpolation; the frame turns with the beam.
TEST_F(ObliqueTable, MatchesIndependentEvaluation) {
    testsupport::context();
    const auto& table = obliqueTableData();
    pathtrace::writeTable(m_dir / "t.bwtable", table);
    model("oblique", "estimate t.bwtable");
    const bssrdf::Model m = load("oblique");
    EXPECT_FALSE(m.attrs.radial);
    EXPECT_FALSE(m.attrs.noWi);
    EXPECT_FALSE(m.attrs.noWo);
    ASSERT_EQ(m.notes.size(), 1u);
    EXPECT_NE(m.notes[0].find("radial, no_wi, no_wo ignored"), std::string::npos) << m.notes[0];
    const Reference ref(table);
    const auto& b = table.settings.bins;

    std::vector<render::BssrdfPair> pairs;
    std::vector<double> expected;
    // Bin centres at θi = 60°, the beam along +x and along an azimuth of 130° (not the last
    // radius: the model is 0 from there on, as a radial table).
    for (double beamAz : {0.0, 130.0 * kPi / 180}) {
        const glm::dvec3 xi(0.4, -0.3, 0.0);
        const double sinI = std::sin(kPi / 3), cosI = std::cos(kPi / 3);
        const glm::dvec3 wi(-sinI * std::cos(beamAz), -sinI * std::sin(beamAz), cosI);
        for (size_t ir = 0; ir + 1 < ref.centres.size(); ++ir)
            for (int is = 0; is < b.thetaSBins; ++is)
                for (int ic = 0; ic < b.dirBins(); ++ic)
                    for (double side : {1.0, -1.0}) {
                        const double ts = side * (is + 0.5) * kPi / b.thetaSBins + beamAz;
                        const double cosO = (ic / b.dirPhiBins + 0.5) / b.dirCosBins;
                        const double phiO =
                            side * (ic % b.dirPhiBins + 0.5) * 2 * kPi / b.dirPhiBins + beamAz;
                        const glm::dvec3 xo =
                            xi + ref.centres[ir] * glm::dvec3(std::cos(ts), std::sin(ts), 0);
                        pairs.push_back(pair(xi, wi, xo, direction(cosO, phiO)));
                        expected.push_back(ref.at(1, ir, size_t(is), size_t(ic)));
                    }
    }
    const size_t centrePairs = pairs.size();
    // Anywhere: random θi (beyond the last angle too), r (beyond the last centre too), θs and
    // an exit direction inside a cell (a margin from its edges).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < 400; ++k) {
        const double thetaI = (0.5 + 79 * u(rng)) * kPi / 180, az = 2 * kPi * u(rng);
        const glm::dvec3 wi(-std::sin(thetaI) * std::cos(az), -std::sin(thetaI) * std::sin(az),
                            std::cos(thetaI));
        const double r = 2.2 * u(rng), ts = 2 * kPi * u(rng);
        const glm::dvec3 xi(u(rng), u(rng), 0);
        const glm::dvec3 xo = xi + r * glm::dvec3(std::cos(ts), std::sin(ts), 0);
        const double cosO = (int(u(rng) * b.dirCosBins) + 0.1 + 0.8 * u(rng)) / b.dirCosBins;
        const double phiO = 2 * kPi * u(rng);
        // off a sector edge (every 90° from the beam axis, on either side)
        if (std::fabs(std::remainder(phiO - az, kPi / 2)) < 0.02) continue;
        const auto p = pair(xi, wi, xo, k % 10 ? direction(cosO, phiO) : glm::dvec3(0, 0, 1));
        pairs.push_back(p);
        expected.push_back(
            ref.eval(glm::dvec3(p.xi), glm::dvec3(p.wi), glm::dvec3(p.xo), glm::dvec3(p.wo)));
    }
    const auto got = evaluate("oblique", pairs);
    ASSERT_EQ(got.size(), pairs.size());
    double scale = 0;
    for (double e : expected)
        scale = std::max(scale, e);
    ASSERT_GT(scale, 0);
    int nonzero = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
        nonzero += expected[i] > 0;
        for (int c = 0; c < 3; ++c) {
            if (i < centrePairs) {
                EXPECT_NEAR(got[i][c], expected[i], 2e-6 * expected[i] + 1e-7 * scale)
                    << "centre pair " << i;
            } else {
                EXPECT_NEAR(got[i][c], expected[i], 1e-5 * scale) << "pair " << i;
            }
        }
    }
    EXPECT_GT(nonzero, 300);
}

// (b) Mirroring y (positions and both directions) leaves the value unchanged; mirroring the
// exit point alone changes the exit cell's azimuth relative to the side and so the value.
TEST_F(ObliqueTable, MirrorSymmetry) {
    testsupport::context();
    pathtrace::writeTable(m_dir / "t.bwtable", obliqueTableData());
    model("oblique", "estimate t.bwtable");
    std::vector<render::BssrdfPair> pairs;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    auto mirror = [](glm::dvec3 v) { return glm::dvec3(v.x, -v.y, v.z); };
    for (int k = 0; k < 100; ++k) {
        const glm::dvec3 wi = glm::normalize(glm::dvec3(u(rng), 0.5 * u(rng), 1.2 + u(rng)));
        const glm::dvec3 xi(u(rng), u(rng), 0), xo(u(rng), u(rng), 0);
        const glm::dvec3 wo = glm::normalize(glm::dvec3(u(rng), u(rng), 1.05 + u(rng)));
        pairs.push_back(pair(xi, wi, xo, wo));
        pairs.push_back(pair(mirror(xi), mirror(wi), mirror(xo), mirror(wo)));
        pairs.push_back(pair(mirror(xi), mirror(wi), mirror(xo), wo));
    }
    const auto got = evaluate("oblique", pairs);
    ASSERT_EQ(got.size(), pairs.size());
    int differ = 0;
    for (size_t k = 0; k < pairs.size(); k += 3) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(got[k + 1][c], got[k][c], 1e-6f * got[k][c]) << k;
        }
        differ += std::fabs(got[k + 2][0] - got[k][0]) > 1e-3f * got[k][0];
    }
    EXPECT_GT(differ, 10) << "the exit azimuth must matter";
}

// At normal incidence the model is the mean over the θs bins with the exit azimuth taken from
// each bin's beam axis.
TEST_F(ObliqueTable, NormalIncidenceIsTheThetaSMean) {
    testsupport::context();
    const auto& table = obliqueTableData();
    pathtrace::writeTable(m_dir / "t.bwtable", table);
    model("oblique", "estimate t.bwtable");
    const Reference ref(table);
    const auto& b = table.settings.bins;
    std::vector<render::BssrdfPair> pairs;
    std::vector<double> expected;
    const glm::dvec3 n(0, 0, 1), xi(0.1, 0.2, 0);
    for (size_t ir = 0; ir + 1 < ref.centres.size(); ++ir)
        for (double az : {0.3, 2.0, -1.0}) {
            const glm::dvec3 xo = xi + ref.centres[ir] * glm::dvec3(std::cos(az), std::sin(az), 0);
            const double cosO = 0.3, phiRel = 0.4; // exit azimuth from the direction to xo
            const glm::dvec3 wo = direction(cosO, az + phiRel);
            double sum = 0;
            for (int k = 0; k < b.thetaSBins; ++k)
                sum += ref.at(0, ir, size_t(k),
                              size_t(ref.cell(cosO, phiRel + (k + 0.5) * kPi / b.thetaSBins)));
            pairs.push_back(pair(xi, n, xo, wo));
            expected.push_back(sum / b.thetaSBins);
        }
    const auto got = evaluate("oblique", pairs);
    ASSERT_EQ(got.size(), pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i)
        EXPECT_NEAR(got[i][1], expected[i], 2e-6 * expected[i]) << i;
}

// (c) One direction cell: at normal incidence (the pencil plot) an oblique table gives the
// radial table's value, the θs mean of R/(1 − R_sp) of θi = 0; a radial table stays radial.
TEST_F(ObliqueTable, OneCellReducesToTheRadialPath) {
    testsupport::context();
    pathtrace::EstimateSettings s;
    s.thetaIDeg = {0.0, 45.0};
    s.bins.rBins = 6;
    s.bins.rMaxMm = 3;
    s.bins.thetaSBins = 2;
    s.paths = 16384;
    const auto oblique = pathtrace::estimateTable(kMedium, s, 0, pathtrace::chunkCount(s));
    pathtrace::writeTable(m_dir / "o.bwtable", oblique);
    model("onecell", "estimate o.bwtable");
    const bssrdf::Model m = load("onecell");
    EXPECT_FALSE(m.attrs.radial);
    EXPECT_TRUE(m.attrs.noWo) << "one cell: no dependence on Wo";

    // The same bins at θi = 0 only with one θs bin: the radial path.
    s.thetaIDeg = {0.0};
    s.bins.thetaSBins = 1;
    pathtrace::writeTable(m_dir / "r.bwtable",
                          pathtrace::estimateTable(kMedium, s, 0, pathtrace::chunkCount(s)));
    model("radial", "estimate r.bwtable");
    const bssrdf::Model rm = load("radial");
    EXPECT_TRUE(rm.attrs.radial);
    EXPECT_TRUE(rm.notes.empty());
    EXPECT_NE(rm.shader->code.find("TableR["), std::string::npos) << "the radial generator";

    const auto slice = oblique.slice(0);
    std::vector<render::BssrdfPair> pairs;
    std::vector<double> expected;
    const glm::dvec3 n(0, 0, 1);
    for (double r : {0.1, 0.25, 0.75, 1.0, 1.25, 2.75, 2.9}) {
        pairs.push_back(pair(glm::dvec3(0), n, glm::dvec3(r, 0, 0), n));
        auto radial = [&](int ir) {
            return 0.5 * (slice.R[size_t(2 * ir)] + slice.R[size_t(2 * ir + 1)]) /
                   (1 - slice.specular);
        };
        const double x = r / 0.5 - 0.5; // centres at 0.25 + 0.5·k
        const int k = std::clamp(int(std::floor(x)), 0, 5);
        expected.push_back(r <= 0.25   ? radial(0)
                           : r >= 2.75 ? 0.0
                                       : (1 - (x - k)) * radial(k) + (x - k) * radial(k + 1));
    }
    const auto got = evaluate("onecell", pairs);
    ASSERT_EQ(got.size(), pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i)
        EXPECT_NEAR(got[i][0], expected[i], 2e-6 * expected[i]) << "r " << pairs[i].xo.x;
}

// A table of one oblique angle only is a non-radial model whose values hold for every
// incidence (clamped θi): with one θs bin and one cell, R(45°)/(1 − R_sp(45°)).
TEST_F(ObliqueTable, SingleObliqueAngleHoldsForEveryIncidence) {
    testsupport::context();
    pathtrace::EstimateSettings s;
    s.thetaIDeg = {45.0};
    s.bins.rBins = 4;
    s.bins.rMaxMm = 2;
    s.bins.thetaSBins = 1;
    s.paths = 16384;
    const auto table = pathtrace::estimateTable(kMedium, s, 0, pathtrace::chunkCount(s));
    pathtrace::writeTable(m_dir / "t45.bwtable", table);
    model("t45", "estimate t45.bwtable");
    const bssrdf::Model m = load("t45");
    EXPECT_FALSE(m.attrs.radial);
    EXPECT_FALSE(m.attrs.noWi);
    EXPECT_TRUE(m.attrs.noWo);
    const auto slice = table.slice(0);
    std::vector<render::BssrdfPair> pairs;
    for (double thetaI : {0.0, 10.0, 45.0, 80.0, 120.0}) {
        const double t = thetaI * kPi / 180;
        pairs.push_back(pair(glm::dvec3(0), glm::dvec3(-std::sin(t), 0, std::cos(t)),
                             glm::dvec3(0.75, 0, 0), glm::dvec3(0, 0, 1)));
    }
    const auto got = evaluate("t45", pairs);
    ASSERT_EQ(got.size(), pairs.size());
    const double expected = slice.R[1] / (1 - slice.specular); // the centre of bin 1
    EXPECT_GT(expected, 0);
    for (size_t i = 0; i < got.size(); ++i)
        EXPECT_NEAR(got[i][2], expected, 2e-6 * expected) << i;
}

// (d) Bad inputs: each a core::Error naming the data file.
TEST_F(ObliqueTable, BadTablesAreErrorsNamingTheFile) {
    auto s = obliqueSettings();
    s.estimator = pathtrace::BssrdfEstimator::Analog; // cheap: only the shape matters here
    auto make = [&](const std::string& name, const pathtrace::EstimateSettings& st,
                    const pathtrace::Medium& m = kMedium) {
        pathtrace::writeTable(m_dir / name,
                              pathtrace::estimateTable(m, st, 0, pathtrace::chunkCount(st)));
    };
    make("r.bwtable", s);
    // other bins in one channel
    auto other = s;
    other.bins.dirPhiBins = 2;
    make("g_bins.bwtable", other);
    model("bins", "estimate r.bwtable g_bins.bwtable r.bwtable");
    expectError("bins", {"materials/g_bins.bwtable", "bins", "materials/r.bwtable"});
    // a channel without one of the angles
    other = s;
    other.thetaIDeg = {0.0};
    make("g_angle.bwtable", other);
    model("angle", "estimate r.bwtable g_angle.bwtable r.bwtable");
    expectError("angle", {"materials/g_angle.bwtable", "theta_i 0 but", "0,60"});
    // another index of refraction in one channel
    make("b_eta.bwtable", s, pathtrace::Medium{0.1, 1.0, 0.0, 1.4});
    model("eta", "estimate r.bwtable r.bwtable b_eta.bwtable");
    expectError("eta", {"materials/b_eta.bwtable", "eta 1.4 differs"});
    // angles out of order, repeated
    other = s;
    other.thetaIDeg = {60.0, 0.0};
    make("unsorted.bwtable", other);
    model("unsorted", "estimate unsorted.bwtable");
    expectError("unsorted", {"materials/unsorted.bwtable", "theta_i 60,0", "increase strictly"});
    other.thetaIDeg = {0.0, 30.0, 30.0};
    make("repeated.bwtable", other);
    model("repeated", "estimate repeated.bwtable");
    expectError("repeated", {"materials/repeated.bwtable", "theta_i 0,30,30"});
    // a negative flux sum (refused by the reader)
    auto table = pathtrace::estimateTable(kMedium, s, 0, pathtrace::chunkCount(s));
    table.tallies[1].binSum[3].add(-1e6);
    pathtrace::writeTable(m_dir / "negative.bwtable", table);
    model("negative", "estimate negative.bwtable");
    expectError("negative", {"materials/negative.bwtable", "negative"});
    // no paths traced
    pathtrace::writeTable(m_dir / "empty.bwtable", pathtrace::estimateTable(kMedium, s, 0, 0));
    model("empty", "estimate empty.bwtable");
    expectError("empty", {"materials/empty.bwtable", "theta_i 0: no paths"});
    // truncated
    const std::string bytes = core::readFile(m_dir / "r.bwtable");
    write("cut.bwtable", bytes.substr(0, bytes.size() - 100));
    model("cut", "estimate cut.bwtable");
    expectError("cut", {"materials/cut.bwtable", "truncated"});
    // too many values: 3 angles x 40 radii x 12 θs bins x 12 cells x 3 > the cap
    other = s;
    other.thetaIDeg = {0.0, 30.0, 60.0};
    other.bins.rBins = 40;
    other.bins.thetaSBins = 12;
    other.bins.dirCosBins = 3;
    other.bins.dirPhiBins = 4;
    ASSERT_GT(3u * 3 * 40 * 12 * 12, bssrdf::kMaxObliqueValues);
    make("big.bwtable", other);
    model("big", "estimate big.bwtable");
    expectError("big", {"materials/big.bwtable",
                        "51840 values, at most " + std::to_string(bssrdf::kMaxObliqueValues),
                        "fewer r, theta_s or direction bins"});
}

// The renderer on a flat plate facing +z (the table's own geometry) lit uniformly: brute force
// M(xo) = Σ E·A·Bssrdf(p_i, +z, xo, +z) at the centre pixel, with the independent values.
TEST_F(ObliqueTable, PlateExitanceMatchesTheTable) {
    testsupport::context();
    const auto& table = obliqueTableData();
    pathtrace::writeTable(m_dir / "t.bwtable", table);
    model("oblique", "estimate t.bwtable");
    const bssrdf::Model m = load("oblique");
    const Reference ref(table);
    bssrdf::Builtins b;
    b.ior = float(kMedium.eta);
    b.scale = 1.0f; // mesh units are mm
    const float thickness = 1.0f, half = 4.0f, h = 0.1f;
    const int k = int(std::lround(2 * half / h));
    std::vector<glm::vec3> p, n, irr;
    std::vector<float> a;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            p.emplace_back(-half + (float(i) + 0.5f) * h, -half + (float(j) + 0.5f) * h,
                           0.5f * thickness);
            n.emplace_back(0.0f, 0.0f, 1.0f);
            a.push_back(h * h);
            irr.emplace_back(1.0f, 2.0f, 0.5f);
        }
    octree::Octree tree = octree::build(p, n, a);
    octree::setIrradiance(tree, irr);
    render::Renderer r(shader::Sources{m_root});
    r.setMesh(mesh::makeThinPlate(2.0 * half, 2.0 * half, thickness));
    r.setOctree(tree);
    r.setModel(m);
    r.setMaterial(bssrdf::defaultValues(m), b);
    render::Settings s;
    s.width = s.height = 8;
    s.camera.target = glm::vec3(0.0f, 0.0f, 0.5f * thickness);
    s.camera.yaw = 0.0f; // camera on +z, looking down at the lit face
    s.camera.pitch = 0.0f;
    s.camera.distance = 20.0f;
    s.camera.radius = 10.0f;
    s.camera.fovY = 0.1f;
    s.bruteForce = true;
    r.render(s);
    const render::Readback rb = r.readback();
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    const size_t centre = rb.index(4, 4);
    ASSERT_EQ(rb.position[centre].w, 1.0f);
    const glm::vec3 xo(rb.position[centre]);
    ASSERT_NEAR(xo.z, 0.5f * thickness, 1e-5f);
    const auto pairs = render::allPointPairs(tree, xo, glm::vec3(0, 0, 1), 1.0f);
    std::vector<glm::vec3> values;
    for (const auto& q : pairs)
        values.emplace_back(
            float(ref.evalNormal(glm::dvec3(q.xi), glm::dvec3(q.xo), glm::dvec3(q.wo))));
    const glm::vec3 expected = render::bruteForceExitance(tree, values, 1.0f);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(expected[c], 0.0f);
        EXPECT_NEAR(rb.exitance[centre][c], expected[c], 1e-4f * expected[c]) << c;
    }
}

// (e) The renderer (hierarchical and brute force, on the bunny) and the lit sphere draw an
// oblique table model without GL errors: finite, non-zero pixels where the surface is.
TEST_F(ObliqueTable, RendersAndLightsTheSphere) {
    testsupport::context();
    pathtrace::writeTable(m_dir / "t.bwtable", obliqueTableData());
    model("oblique", "estimate t.bwtable");
    const bssrdf::Model m = load("oblique");
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(float(kMedium.sigmaA));
    b.sigmaS = glm::vec3(float(kMedium.sigmaS));
    b.ior = float(kMedium.eta);
    b.scale = 5.0f; // a bunny 5 mm long: the table's 2 mm reach spans much of it

    mesh::Mesh bunny = mesh::loadObj(m_root / "third_party/bunny/bunny.obj");
    mesh::normalizeMesh(bunny, "bunny");
    const pointcloud::PointCloud pc = pointcloud::sampleUniform(bunny, 2000, 3);
    std::vector<glm::vec3> p, n, e;
    std::vector<float> a;
    const glm::vec3 light = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
    for (const auto& q : pc.points) {
        p.emplace_back(q.p[0], q.p[1], q.p[2]);
        n.emplace_back(q.n[0], q.n[1], q.n[2]);
        a.push_back(q.area);
        e.push_back(glm::vec3(std::max(0.0f, glm::dot(n.back(), light))));
    }
    octree::Octree tree = octree::build(p, n, a);
    octree::setIrradiance(tree, e);
    render::Renderer r(shader::Sources{m_root});
    r.setMesh(bunny);
    r.setOctree(tree);
    r.setModel(m);
    r.setMaterial(bssrdf::defaultValues(m), b);
    render::Settings s;
    s.width = 48;
    s.height = 36;
    s.camera.aspect = 48.0f / 36.0f;
    s.camera.fit(bunny);
    for (bool brute : {false, true}) {
        s.bruteForce = brute;
        r.render(s);
        const render::Readback rb = r.readback();
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        size_t hits = 0, lit = 0;
        for (size_t i = 0; i < rb.position.size(); ++i) {
            if (rb.position[i].w != 1.0f) continue;
            ++hits;
            EXPECT_EQ(rb.stats[i].z, 0u) << "flags at pixel " << i;
            for (int c = 0; c < 3; ++c) {
                EXPECT_TRUE(std::isfinite(rb.hdr[i][c]) && rb.hdr[i][c] >= 0) << i;
            }
            lit += rb.hdr[i][0] > 0;
        }
        EXPECT_GT(hits, 200u) << "brute force " << brute;
        EXPECT_GT(lit, hits / 2) << "brute force " << brute;
    }

    const auto sphere = bssrdf::buildModelProgram(m, "sphere_bssrdf.comp", shader::Sources(m_root));
    bssrdf::SphereIntegrator integ;
    litsphere::Setup setup;
    setup.radiusMm = 2.0;
    setup.width = setup.height = 16;
    setup.lightDir[0] = 0.5;
    setup.lightDir[2] = 1.0;
    integ.reset(setup);
    integ.step(sphere.id(), m, bssrdf::defaultValues(m), b, 256);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    const litsphere::Image img = integ.image();
    size_t positive = 0;
    for (float v : img.mean) {
        EXPECT_TRUE(std::isfinite(v) && v >= 0);
        positive += v > 0;
    }
    EXPECT_GT(positive, 3u * 100u) << "the lit sphere is not empty";
}

} // namespace
