// render/profile_table: rMax choice, grid, GPU fill and CPU lookup of the radial profile table
// (see profile_table.h).
#include "render/profile_table.h"

#include <algorithm>
#include <cmath>

namespace render {

float profileRadius(float rMax, int k, int count) {
    const double t = static_cast<double>(k) / static_cast<double>(count - 1);
    return static_cast<float>(static_cast<double>(rMax) * t * t);
}

glm::vec3 lookupProfile(const ProfileTable& table, float r) {
    const auto count = static_cast<uint32_t>(table.values.size());
    if (count < 2) return glm::vec3(0.0f);
    const float last = static_cast<float>(count - 1u);
    const float t = std::sqrt(r / table.rMax) * last;
    if (!(t < last)) return glm::vec3(0.0f);
    const auto i = static_cast<uint32_t>(t);
    const float f = t - static_cast<float>(i);
    const glm::vec3 a = table.values[i];
    const glm::vec3 b = table.values[i + 1u];
    return a + f * (b - a);
}

float chooseProfileRadius(const std::vector<double>& radii, const std::vector<glm::dvec3>& values,
                          double capMm) {
    glm::dvec3 ref(0.0);
    for (int c = 0; c < 3; ++c) {
        const double r0 = values.empty() ? 0.0 : values[0][c];
        if (std::isfinite(r0) && r0 > 0.0) {
            ref[c] = r0;
            continue;
        }
        for (const auto& v : values)
            if (std::isfinite(v[c])) ref[c] = std::max(ref[c], std::fabs(v[c]));
    }
    // last probe (r > 0) where some channel is above the decay threshold or not a number: NaN
    // and Inf stay inside the table, so they reach the image (magenta) instead of vanishing
    size_t last = 0;
    for (size_t j = 1; j < radii.size(); ++j)
        for (int c = 0; c < 3; ++c) {
            const double v = values[j][c];
            if (!std::isfinite(v) || (ref[c] > 0.0 && std::fabs(v) > kProfileDecay * ref[c]))
                last = j;
        }
    // ... and, for profiles singular at 0 (R ~ 1/r: the peak says nothing about the tail), the
    // last probe beyond which some channel still holds more than kProfileEnergyTail of its
    // energy 2π∫R r dr (trapezoids in ln r of R r²)
    for (int c = 0; c < 3; ++c) {
        std::vector<double> tail(radii.size(), 0.0); // energy beyond probe j
        for (size_t j = radii.size() - 1; j > 1; --j) {
            const double a = values[j - 1][c] * radii[j - 1] * radii[j - 1],
                         b = values[j][c] * radii[j] * radii[j];
            tail[j - 1] = tail[j] + 0.5 * (a + b) * std::log(radii[j] / radii[j - 1]);
        }
        const double total = tail.size() > 1 ? tail[1] : 0.0;
        if (!(std::isfinite(total) && total > 0.0)) continue;
        for (size_t j = 1; j < radii.size(); ++j)
            if (tail[j] > kProfileEnergyTail * total) last = std::max(last, j);
    }
    double rMax = radii.size() > 1 ? radii[std::min(last + 1, radii.size() - 1)] : 1.0;
    if (capMm > 0.0) rMax = std::min(rMax, capMm);
    return static_cast<float>(rMax);
}

ProfileTable buildProfileTable(GLuint pencilProgram, const bssrdf::Model& m,
                               const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                               double capMm) {
    std::vector<double> probe{0.0};
    for (int j = 0; j <= 256; ++j)
        probe.push_back(static_cast<double>(static_cast<float>(1e-4 * std::pow(10.0, j / 32.0))));
    const bssrdf::Profile p = bssrdf::evaluateProfile(pencilProgram, m, values, b, probe);
    ProfileTable t;
    t.rMax = chooseProfileRadius(p.r, p.value, capMm);
    std::vector<double> grid(kProfileEntries);
    for (int k = 0; k < kProfileEntries; ++k)
        grid[k] = profileRadius(t.rMax, k, kProfileEntries);
    const bssrdf::Profile q = bssrdf::evaluateProfile(pencilProgram, m, values, b, grid);
    t.values.resize(kProfileEntries);
    for (int k = 0; k < kProfileEntries; ++k)
        t.values[k] = glm::vec3(q.value[k]);
    return t;
}

} // namespace render
