// pathtrace/validate: input checks at the boundary of the tracers (core::Error naming the
// field). The hot loops assume what is checked here: σt > 0 and finite, 0 <= α <= 1, |g| < 1
// (HG is a density only there), η > 0 finite (Fresnel), a histogram that fits in memory.
#include "core/core.h"
#include "core/text.h"
#include "pathtrace/pathtrace.h"

#include <cmath>
#include <string>

namespace pathtrace {
void validate(const Medium& m, const std::string& what) {
    if (!std::isfinite(m.sigmaA) || m.sigmaA < 0)
        throw core::Error(
            what, 0, "sigma_a must be finite and >= 0 (1/mm), got " + core::formatNumber(m.sigmaA));
    if (!std::isfinite(m.sigmaS) || m.sigmaS <= 0)
        throw core::Error(
            what, 0, "sigma_s must be finite and > 0 (1/mm), got " + core::formatNumber(m.sigmaS));
    if (!std::isfinite(m.sigmaA + m.sigmaS))
        throw core::Error(what, 0, "sigma_a + sigma_s overflows");
    if (!std::isfinite(m.g) || !(std::fabs(m.g) < 1))
        throw core::Error(what, 0, "g must lie in (-1, 1), got " + core::formatNumber(m.g));
    if (!std::isfinite(m.eta) || m.eta <= 0)
        throw core::Error(what, 0, "eta must be finite and > 0, got " + core::formatNumber(m.eta));
}

void validate(const Termination& t, const std::string& what) {
    if (!(t.rouletteWeight > 0 && t.rouletteWeight < 1))
        throw core::Error(what, 0,
                          "rouletteWeight must lie in (0, 1), got " +
                              core::formatNumber(t.rouletteWeight));
    if (!(t.rouletteSurvival > 0 && t.rouletteSurvival <= 1))
        throw core::Error(what, 0,
                          "rouletteSurvival must lie in (0, 1], got " +
                              core::formatNumber(t.rouletteSurvival));
    if (t.maxEvents < 1)
        throw core::Error(what, 0, "maxEvents must be >= 1, got " + std::to_string(t.maxEvents));
}

void validate(const Splitting& s, const std::string& what) {
    if (s.levels < 0 || s.levels > 10)
        throw core::Error(what, 0,
                          "splitting levels must lie in [0, 10], got " + std::to_string(s.levels));
    if (!(std::isfinite(s.startLd) && s.startLd >= 0))
        throw core::Error(what, 0,
                          "splitting start must be finite and >= 0 (diffusion lengths), got " +
                              core::formatNumber(s.startLd));
    if (!(std::isfinite(s.stepLd) && s.stepLd >= 1e-3))
        throw core::Error(what, 0,
                          "splitting step must be finite and >= 0.001 (diffusion lengths), got " +
                              core::formatNumber(s.stepLd));
    if (!(std::isfinite(s.depth) && s.depth >= 0))
        throw core::Error(
            what, 0, "splitting depth must be finite and >= 0, got " + core::formatNumber(s.depth));
}

void validate(const ExpectedExits& e, const std::string& what) {
    if (e.samples < 0 || e.samples > 64)
        throw core::Error(what, 0,
                          "exit samples must lie in [0, 64] (0: actual exits), got " +
                              std::to_string(e.samples));
    if (!(std::isfinite(e.depthMfp) && e.depthMfp >= 0))
        throw core::Error(what, 0,
                          "exit depth must be finite and >= 0 (mean free paths), got " +
                              core::formatNumber(e.depthMfp));
}

void validate(const SlabSettings& s) {
    const std::string what = "slab settings";
    if (!std::isfinite(s.rMaxMm) || s.rMaxMm <= 0)
        throw core::Error(
            what, 0, "rMax must be a finite length > 0 mm, got " + core::formatNumber(s.rMaxMm));
    if (s.bins < 1) throw core::Error(what, 0, "bins must be >= 1, got " + std::to_string(s.bins));
    if (s.bins > 10000000)
        throw core::Error(
            what, 0, "bins: more bins than memory allows (" + std::to_string(s.bins) + " > 10^7)");
    if (s.paths == 0) throw core::Error(what, 0, "paths must be >= 1");
    if (s.paths > 10000000000000ull)
        throw core::Error(what, 0,
                          "paths: absurd path count " + std::to_string(s.paths) + " (> 10^13)");
    if (s.threads < 0)
        throw core::Error(what, 0,
                          "threads must be >= 0 (0: all hardware threads), got " +
                              std::to_string(s.threads));
    validate(s.termination, what);
    validate(s.splitting, what);
    validate(s.exits, what);
    if (s.estimator != Estimator::Implicit && s.estimator != Estimator::Analog &&
        s.estimator != Estimator::Connections)
        throw core::Error(what, 0, "estimator: unknown value");
}

} // namespace pathtrace
