// Shared by the irradiance tests: an independent Fresnel reference (pathtrace/fresnel.h), the
// hemispherical integral of Ft by 1D quadrature, meshes, raw EXR writing (bypassing the
// module's validation, for bad-input tests) and the one Stage per GL test binary.
#pragma once

#include "../support/raw_exr.h"
#include "../support/scratch_dir.h"

#include "irradiance/irradiance.h"
#include "pathtrace/fresnel.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <unistd.h>
#include <vector>

namespace irrtest {

inline double ft(double mu, double eta) {
    return mu <= 0 ? 0.0 : 1.0 - pathtrace::fresnelDielectric(mu, eta);
}

// 2π ∫_0^1 Ft(μ) μ dμ = π (1 − F_dr) by composite Simpson (20000 intervals; the integrand is
// smooth on [0, 1], error far below 1e-9).
inline double hemisphericalFt(double eta) {
    const int n = 20000;
    double s = 0;
    for (int i = 0; i <= n; ++i) {
        const double mu = double(i) / n;
        const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        s += w * ft(mu, eta) * mu;
    }
    return 2.0 * std::numbers::pi * s / (3.0 * n);
}

inline std::filesystem::path tempDir(const std::string& tag) {
    const auto d = std::filesystem::temp_directory_path() /
                   ("bw_irr_" + tag + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    testsupport::removeAtExit(d);
    return d;
}

using testsupport::writeRawExr;

inline irradiance::EnvironmentMap constantEnv(int w, int h, glm::vec3 c) {
    irradiance::EnvironmentMap e;
    e.width = w;
    e.height = h;
    for (int i = 0; i < w * h; ++i) {
        e.rgb.push_back(c.r);
        e.rgb.push_back(c.g);
        e.rgb.push_back(c.b);
    }
    return e;
}

// Appends `b` translated by `offset` to `a`.
inline void append(mesh::Mesh& a, const mesh::Mesh& b, glm::vec3 offset) {
    const uint32_t base = static_cast<uint32_t>(a.vertices.size());
    for (size_t i = 0; i < b.vertices.size(); ++i) {
        a.vertices.push_back({b.vertices[i][0] + offset.x, b.vertices[i][1] + offset.y,
                              b.vertices[i][2] + offset.z});
        a.normals.push_back(b.normals[i]);
    }
    for (const auto& t : b.triangles)
        a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

} // namespace irrtest
