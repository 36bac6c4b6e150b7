// The parameterization lab: what the reference tracer measures for the σ each artist mapping
// (param_mappings.h) produces. For every mapping × η × g × asked albedo A (length d), the medium
// the mapping gives is path traced (the slab reference of the scores, cached) and the lab
// records the measured total diffuse reflectance per unit power entering, A_meas =
// R_d/(1 − R_sp) with its standard error, and the mean exit radius r̄ = Σ r R(r) r dr / Σ R(r) r dr
// over the reference's range [0, 4.5 l_d) against d. With `diffuse`, also the albedo under
// uniform diffuse light, A_diff = Σ w μ R_d(μ) / Σ w μ (1 − R_sp(μ)) over 8 Gauss–Legendre
// cosines μ of incidence (the whole-BSSRDF walk's total exits at each angle): the albedo a
// mapping fitted to diffuse illumination (van de Hulst's) promises. A mapping that keeps its
// promise has A_meas = A at every η and g, and r̄/d the same for every A (the length means one
// thing).
#pragma once

#include "material/material.h"
#include "pathtrace/pathtrace.h"
#include "pipeline/param_mappings.h"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace app {

class Workbench;

// Reference paths per measured case: the CLI's --paths default and the Parameters panel's.
inline constexpr uint64_t kLabPaths = 100000;

struct LabSettings {
    std::vector<std::string> mappings; // ids; empty: every mapping
    std::vector<double> albedos{0.1, 0.3, 0.5, 0.7, 0.9};
    std::vector<double> etas{1.0, 1.3, 1.5};
    std::vector<double> gs{0.0, 0.8};
    double lengthMm = 1.0;
    uint64_t paths = kLabPaths;
    bool diffuse = true; // also the albedo under diffuse light (8 incidence angles)
};

struct LabCase {
    std::string mapping;
    double eta = 1, g = 0, albedo = 0, lengthMm = 1;
    double sigmaA = 0, sigmaS = 0;         // what the mapping gave (1/mm)
    double measured = 0, measuredSe = 0;   // A_meas and its se
    double meanRadiusMm = 0;               // r̄
    double diffuse = NAN, diffuseSe = NAN; // A_diff and its se (NaN when not measured)
    std::string problem;                   // the mapping could not reach A, or the trace failed
};

// Runs every case (cached references make a rerun cheap); `progress(done, total)` after each,
// `cancel` stops between cases. `wb` must hold the models the mappings invert (its library
// is searched by path). Throws core::Error naming an unknown mapping.
std::vector<LabCase> runParamsLab(Workbench& wb, const LabSettings& s,
                                  const std::function<void(size_t, size_t)>& progress = {},
                                  const std::atomic<bool>* cancel = nullptr);

// One medium's measurement (the slab reference of `paths` paths for channel 0 of p; with
// `diffuse`, `paths` more per incidence angle for A_diff).
void measureLabCase(const material::MaterialParams& p, uint64_t paths, LabCase& c,
                    bool diffuse = true);
// The albedo under uniform diffuse light and its standard error (see above).
std::pair<double, double> diffuseAlbedo(const pathtrace::Medium& m, uint64_t paths);

} // namespace app
