// material parameters: validation, derived diffusion quantities, swatch colours.
#include "material.h"

#include "core/color.h"
#include "core/core.h"
#include "detail/messages.h"

#include <cmath>

namespace material {

void validate(const MaterialParams& p, const std::string& what) {
    // g first: σs derived from a preset's σ′s/(1 − g) is infinite or negative for a bad g.
    if (!std::isfinite(p.g) || std::abs(p.g) >= 1)
        throw core::Error(
            what, 0, "g (mean cosine) must satisfy |g| < 1, got " + core::formatNumber(p.g, 6));
    for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(p.sigmaA[c]) || !std::isfinite(p.sigmaS[c]))
            throw core::Error(what, 0,
                              std::string("sigma_a and sigma_s must be finite (channel ") +
                                  detail::channelName(c) + ")");
        if (p.sigmaA[c] < 0)
            throw core::Error(what, 0,
                              std::string("sigma_a must be >= 0 1/mm (channel ") +
                                  detail::channelName(c) + " is " +
                                  core::formatNumber(p.sigmaA[c], 6) + ")");
        if (p.sigmaS[c] <= 0)
            throw core::Error(what, 0,
                              std::string("sigma_s must be > 0 1/mm (channel ") +
                                  detail::channelName(c) + " is " +
                                  core::formatNumber(p.sigmaS[c], 6) + ")");
    }
    if (!std::isfinite(p.eta) || p.eta <= 0)
        throw core::Error(what, 0,
                          "eta (relative index of refraction) must be > 0, got " +
                              core::formatNumber(p.eta, 6));
    if (!std::isfinite(p.scale) || p.scale <= 0)
        throw core::Error(what, 0,
                          "scale (mm per unit) must be > 0, got " + core::formatNumber(p.scale, 6));
}

glm::dvec3 reducedAlbedo(const MaterialParams& p) {
    glm::dvec3 sps = p.sigmaS * (1.0 - p.g);
    return sps / (sps + p.sigmaA);
}

glm::dvec3 diffuseMeanFreePath(const MaterialParams& p) {
    glm::dvec3 spt = p.sigmaS * (1.0 - p.g) + p.sigmaA;
    glm::dvec3 ld;
    for (int c = 0; c < 3; ++c) {
        double sigmaTr = std::sqrt(3.0 * p.sigmaA[c] * spt[c]);
        ld[c] = sigmaTr > 0 ? 1.0 / sigmaTr : INFINITY;
    }
    return ld;
}

glm::dvec3 swatch(const glm::dvec3& rgb) {
    double l = core::luminance(rgb);
    if (!(l > 0) || !std::isfinite(l)) return glm::dvec3(0.75);
    return rgb * (0.75 / l);
}

} // namespace material
