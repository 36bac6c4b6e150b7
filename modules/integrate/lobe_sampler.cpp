// A model's Gaussian lobes (the lobe interface QdLobeCount / QdLobe, materials/README.md) as
// its radial distributions: per channel a sampling::GaussianLobes (one-sample MIS over the lobes
// of King et al. 2013), the lobes read on the GPU after init(). Checked against the tabulated
// profile (detail/model_samplers.h), a failure being core::Error(model path, line of
// `vec2 QdLobe(`, "channel X: …"):
//   - the lobes themselves (gaussian_lobes.h: finite weights >= 0, variances > 0, some energy);
//   - energy: |Σ_k w_k / E − 1| <= kEnergyTolerance, E the table's 2π∫R r dr (the table is the
//     same profile on 4096 radii out to where R has decayed by 1e-7);
//   - shape: the lobes' pdf_area against the profile's within the lobes' R_m
//     (profile_agreement.cpp) on kShapePoints radii r_i = R_m (i/kShapePoints)².
//   Measured for quantized_diffusion.bssrdf at Skin1: energy 1.3e-4 apart at worst (red), shape
//   1.4e-4; its lobes with a weight 10 % off or variances 50 % off fail (model_sampler_test).
#include "integrate/detail/model_samplers.h"

#include "core/core.h"
#include "core/text.h"
#include "sampling/gaussian_lobes.h"

#include <cmath>

namespace integrate::detail {

namespace {
constexpr double kEnergyTolerance = 1e-3;
constexpr int kShapePoints = 4096;
} // namespace

Distributions lobeDistributions(GLuint pencilProgram, const bssrdf::Model& m,
                                const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                const std::array<sampling::TabulatedRadial, 3>& table,
                                double energyLoss) {
    const auto lobes = bssrdf::evaluateLobes(pencilProgram, m, values, b);
    Distributions out;
    for (int c = 0; c < 3; ++c) {
        auto error = [&](const std::string& msg) {
            return core::Error(m.path, m.lobesLine,
                               channelLabel(c) + "the Gaussian lobes (QdLobe) " + msg);
        };
        std::vector<sampling::GaussianLobe> l;
        for (const glm::dvec2& wv : lobes[size_t(c)])
            l.push_back({wv.x, wv.y});
        std::unique_ptr<sampling::GaussianLobes> d;
        try {
            d = std::make_unique<sampling::GaussianLobes>(std::move(l), energyLoss, c, m.path);
        } catch (const core::Error& e) {
            std::string why = e.message();
            const std::string own = "channel " + std::to_string(c) + ": ";
            if (why.starts_with(own)) why = why.substr(own.size());
            throw error("cannot be sampled: " + why);
        }
        const sampling::TabulatedRadial& t = table[size_t(c)];
        const double ratio = d->totalEnergy() / t.totalEnergy();
        if (!(std::abs(ratio - 1) <= kEnergyTolerance))
            throw error("hold " + core::formatNumber(d->totalEnergy(), 6) +
                        " of energy, the profile " + core::formatNumber(t.totalEnergy(), 6) +
                        " (2 pi int R r dr); tolerance " + core::formatNumber(kEnergyTolerance, 3) +
                        " relative");
        std::vector<double> r, pdf;
        for (int i = 0; i <= kShapePoints; ++i) {
            const double f = double(i) / kShapePoints;
            r.push_back(d->radiusMax() * f * f);
            pdf.push_back(d->pdfArea(r.back()));
        }
        if (std::string p = agreementProblem(t, d->radiusMax(), r, pdf, energyLoss); !p.empty())
            throw error("do not reproduce the model's profile: " + p);
        out[size_t(c)] = std::move(d);
    }
    return out;
}

} // namespace integrate::detail
