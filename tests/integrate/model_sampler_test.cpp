// A model's own radial distributions (integrate/radial_source.h): the analytic sampler of a
// `::begin sample` section and the Gaussian lobes of the lobe interface, read on the GPU.
//   - tests/integrate/data/gaussian_sampler.bssrdf (one planar Gaussian per channel, closed-form
//     inverse) is sampled through its section: R_m is its MaxRadius, the CPU distribution follows
//     the closed form;
//   - every check names the model file and the `::begin sample` line: a section that does not
//     compile (the driver's error on its own line), MaxRadius not > 0, NaN, a negative pdf, a pdf
//     that does not integrate to 1, radii beyond MaxRadius, an inverse that is not the inverse,
//     a sampler of another profile, a MaxRadius that gives up too much energy;
//   - quantized_diffusion.bssrdf is sampled through its lobes, and lobes that do not reproduce
//     the profile (energy, shape), a bad count and a negative weight name the QdLobe line.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "core/core.h"
#include "integrate/radial_source.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/inverse_cdf_radial.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using testsupport::lineOf;
using testsupport::replaced;

namespace {

const std::string kGaussian = "tests/integrate/data/gaussian_sampler.bssrdf";

// Skin1 of Jensen et al. 2001 (σs', σa in 1/mm, η 1.3).
bssrdf::Builtins skin1() {
    bssrdf::Builtins b;
    b.sigmaA = {0.032f, 0.17f, 0.48f};
    b.sigmaS = {0.74f, 0.88f, 1.01f};
    b.ior = 1.3f;
    return b;
}

// The variance (mm²) of the Gaussian model per channel at Skin1, Width 2, in double.
double gaussianVariance(int c) {
    const bssrdf::Builtins b = skin1();
    const double sa = b.sigmaA[c], st = sa + b.sigmaS[c];
    return 4 / (3 * sa * st);
}

std::string text(const std::string& rel) {
    return testsupport::readText(testsupport::sourceRoot() / rel);
}

// radialSource for a model given as text (display path `path`).
integrate::RadialSource sourceOf(const std::string& modelText, const std::string& path) {
    testsupport::context();
    const bssrdf::Model m = bssrdf::parseModel(modelText, path);
    shader::Sources src{testsupport::sourceRoot()};
    gl::Program p = bssrdf::buildModelProgram(m, "pencil_profile.comp", src);
    return integrate::radialSource(p.id(), m, bssrdf::defaultValues(m), skin1(), 1e-3, path);
}

// The error radialSource (or the build) throws for `modelText`: it must name `path` and `line`
// and contain `fragment`.
void expectError(const std::string& modelText, const std::string& path, int line,
                 const std::string& fragment) {
    try {
        sourceOf(modelText, path);
        ADD_FAILURE() << "accepted; expected: " << fragment;
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), path) << e.what();
        EXPECT_EQ(e.line(), line) << e.what();
        EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
    }
}

// The sample section of the Gaussian model with `from` replaced by `to` everywhere in it.
std::string sampleReplaced(const std::string& from, const std::string& to) {
    std::string t = text(kGaussian);
    const size_t begin = t.find("::begin sample");
    std::string head = t.substr(0, begin), sample = t.substr(begin);
    for (size_t at = sample.find(from); at != std::string::npos;
         at = sample.find(from, at + to.size()))
        sample = sample.substr(0, at) + to + sample.substr(at + from.size());
    return head + sample;
}

} // namespace

TEST(AnalyticSampler, TheSectionIsSampledAndFollowsItsClosedForm) {
    const integrate::RadialSource s = sourceOf(text(kGaussian), kGaussian);
    EXPECT_EQ(s.kind, "analytic sampler");
    for (int c = 0; c < 3; ++c) {
        const auto* d = dynamic_cast<const sampling::InverseCdfRadial*>(s.channel[size_t(c)].get());
        ASSERT_NE(d, nullptr);
        const double v = gaussianVariance(c), loss = 1e-5;
        const double rm = std::sqrt(2 * v * std::log(1 / loss));
        EXPECT_NEAR(d->radiusMax() / rm, 1.0, 1e-5) << c; // float MaxRadius
        // the CDF at the knots is the float SampleRadius': 1e-4 in probability. The density
        // of annuli 1/65536 wide in probability carries SampleRadius' float rounding (an
        // absolute ~6e-8 in ln(1 − ξ) against a width 1.5e-5: measured 0.6 %): 2 %
        for (double u = 0.01; u < 0.995; u += 0.01) {
            const double r = std::sqrt(-2 * v * std::log1p(-u * (1 - loss)));
            EXPECT_NEAR(d->cdf(r), u, 1e-4) << c << " " << u;
            const double pdf = std::exp(-r * r / (2 * v)) / (2 * M_PI * v * (1 - loss));
            EXPECT_NEAR(d->pdfArea(r) / pdf, 1.0, 2e-2) << c << " " << u;
        }
        EXPECT_NEAR(d->totalEnergy(), 0.5, 1e-4); // the parameter Energy
    }
}

TEST(AnalyticSampler, ChecksNameTheFileAndTheSectionLine) {
    const std::string path = "tests/integrate/data/bad.bssrdf";
    const int line = lineOf(text(kGaussian), "::begin sample");
    const std::string pdf = "    return r/v*exp(-r*r/(2.0*v))/(1.0 - Loss);";
    struct Case {
        const char* what;
        std::string model;
        const char* fragment;
    };
    const Case cases[] = {
        {"MaxRadius", sampleReplaced("return sqrt(2.0*V[channel]*log(1.0/Loss));", "return -1.0;"),
         "channel R: MaxRadius must be finite and > 0"},
        {"NaN",
         replaced(text(kGaussian), pdf,
                  "    if (r > 0.5*MaxRadius(channel)) return uintBitsToFloat(0x7fc00000u);\n" +
                      pdf),
         "channel R: PdfRadius is NaN at r = "},
        {"negative",
         replaced(text(kGaussian), pdf,
                  "    if (r > 0.9*MaxRadius(channel)) return -1e-3;\n" + pdf),
         "channel R: PdfRadius is negative (-0.001) at r = "},
        {"not normalised",
         replaced(text(kGaussian), pdf, "    return 1.05*r/v*exp(-r*r/(2.0*v))/(1.0 - Loss);"),
         "so its integral over [0, MaxRadius = "},
        {"beyond MaxRadius", sampleReplaced("return min(r,", "return 1.01*min(r,"),
         "beyond MaxRadius = "},
        {"not the inverse", sampleReplaced("sqrt(-2.0*V[channel]", "sqrt(-2.2*V[channel]"),
         "SampleRadius is not the inverse of the CDF of PdfRadius"},
        {"another profile", sampleReplaced("V[channel]", "1.1*V[channel]"),
         "does not describe the model's profile: its pdf_area differs"},
        {"too small", sampleReplaced("const float Loss = 1e-5;", "const float Loss = 1e-2;"),
         "does not describe the model's profile: the sampler's radius"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        expectError(c.model, path, line, c.fragment);
    }
}

TEST(AnalyticSampler, ASectionThatDoesNotCompileIsReportedOnItsLine) {
    const std::string bad =
        replaced(text(kGaussian), "    float v = V[channel];", "    float v = V[channel] +* ;");
    expectError(bad, "tests/integrate/data/broken.bssrdf", lineOf(bad, "+* ;"), "");
    // and a name only the sample section defines is unknown to the other sections
    const std::string outside = replaced(text(kGaussian), "    float R2 = dot(Xo - Xi, Xo - Xi);",
                                         "    float R2 = dot(Xo - Xi, Xo - Xi) + MaxRadius(0);");
    expectError(outside, "tests/integrate/data/outside.bssrdf", lineOf(outside, "+ MaxRadius(0)"),
                "MaxRadius");
}

TEST(ModelLobes, QuantizedDiffusionIsSampledThroughItsLobes) {
    const std::string path = "materials/quantized_diffusion.bssrdf";
    const integrate::RadialSource s = sourceOf(text(path), path);
    EXPECT_EQ(s.kind, "Gaussian lobes");
    for (int c = 0; c < 3; ++c) {
        const auto* d = dynamic_cast<const sampling::GaussianLobes*>(s.channel[size_t(c)].get());
        ASSERT_NE(d, nullptr);
        EXPECT_EQ(d->lobes().size(), 40u);
        EXPECT_NEAR(d->keptEnergy() / d->totalEnergy(), 1 - 1e-3, 1e-9);
    }
}

TEST(ModelLobes, LobesThatDoNotReproduceTheProfileAreNamed) {
    const std::string qd = text("materials/quantized_diffusion.bssrdf");
    const std::string lobe = "    return vec2(QdWeight[k][channel], QdVariance[k][channel]);";
    const std::string path = "materials/qd_bad.bssrdf";
    const int line = lineOf(qd, "vec2 QdLobe(int k");
    expectError(
        replaced(qd, lobe, "    return vec2(1.1*QdWeight[k][channel], QdVariance[k][channel]);"),
        path, line, "channel R: the Gaussian lobes (QdLobe) hold ");
    expectError(
        replaced(qd, lobe, "    return vec2(QdWeight[k][channel], 1.5*QdVariance[k][channel]);"),
        path, line, "channel R: the Gaussian lobes (QdLobe) do not reproduce the model's profile");
    expectError(replaced(qd, lobe,
                         "    return vec2(k == 3 ? -1.0 : QdWeight[k][channel], "
                         "QdVariance[k][channel]);"),
                path, line, "cannot be sampled: lobe 3: weight is negative (-1)");
    expectError(
        replaced(qd, "int QdLobeCount() { return QD_LOBES; }", "int QdLobeCount() { return 0; }"),
        path, line, "QdLobeCount() must return 1");
}
