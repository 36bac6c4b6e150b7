// The BSSRDF slice's settings (GUI, CLI and captures share them) and the snapshot its runners
// publish (slice_stage.h: the CPU runner; slice_gpu.h: the GL one).
#pragma once

#include "core/limits.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/tracer_device.h"

#include <optional>
#include <string>

namespace app {

struct SliceSettings {
    bool enabled = false; // the GUI sets it while the slice panel shows
    int channel = 0;      // the medium of colour channel 0 R, 1 G, 2 B
    double thetaIDeg = 45.0;
    double rangeLd = 3.0; // r_max = range_ld · l_d of the channel
    int rBins = 16;
    bool logR = false;
    int thetaSBins = 12;
    int dirCosBins = 2, dirPhiBins = 6;
    uint64_t paths = 200000;
    uint64_t seed = 1;
    pathtrace::BssrdfEstimator estimator = pathtrace::BssrdfEstimator::Connections;
    pathtrace::ScatterOrders orders = pathtrace::ScatterOrders::All;
    // Expected-value exits of the CPU histogram walks (pathtrace.h, ExpectedExits; analog and
    // implicit): directions scored per collision near the surface, 0 for the actual exits.
    int exitSamples = pathtrace::ExpectedExits{}.samples;
    // auto: the GL walk (a slice per frame) where the GL tracer measured faster than the CPU
    // walk on this machine (tracer_device.h; the slab probe decides for both walks)
    TracerDevice device = TracerDevice::Auto;
};
template <class V> void fields(V& v, SliceSettings& s) {
    v("enabled", s.enabled, "path-trace the BSSRDF slice");
    v("channel", s.channel, "medium of colour channel 0 R, 1 G, 2 B", core::Limits{0, 2});
    v("theta_i_deg", s.thetaIDeg, "incidence angle, degrees [0, 90)", core::Limits{0, 90});
    v("range_ld", s.rangeLd, "radius of the last bin edge in l_d of the channel",
      core::Limits{0.01, 1000});
    v("r_bins", s.rBins, "radial bins", core::Limits{1, 1e4});
    v("log_r", s.logR, "logarithmic radial bins");
    v("theta_s_bins", s.thetaSBins, "bins of theta_s over [0, 180] deg", core::Limits{1, 1e4});
    v("dir_cos_bins", s.dirCosBins, "exit-direction rings (equal solid angle)",
      core::Limits{1, 1e3});
    v("dir_phi_bins", s.dirPhiBins, "exit-direction azimuth sectors", core::Limits{1, 1e3});
    v("paths", s.paths, "photon paths", core::Limits{1, 1e18});
    v("seed", s.seed, "random seed");
    v("estimator", s.estimator, "estimator");
    v("orders", s.orders, "scattering orders tallied");
    v("exit_samples", s.exitSamples,
      "expected-value exits: directions scored per collision near the surface (0: the actual "
      "exits; CPU histogram walks)",
      core::Limits{0, 64});
    v("device", s.device, "auto: the GPU where it measured faster than the CPU, else the CPU");
}

// The estimate settings and medium of a slice (validated by the runner, not here). r_max is
// range_ld · l_d; where l_d is infinite (σa = 0) it is range_ld · 10 transport mean free paths.
pathtrace::EstimateSettings estimateSettings(const SliceSettings& s, const pathtrace::Medium& m);

struct SliceSnapshot {
    bool running = false;
    uint64_t pathsDone = 0, pathsTarget = 0;
    double pathsPerSecond = 0;
    pathtrace::Medium medium;
    pathtrace::EstimateSettings settings;        // of the table below (paths = pathsDone)
    std::optional<pathtrace::BssrdfSlice> slice; // none until the first chunks are done
    std::string problem;                         // bad settings: nothing new runs
    std::string energy;                          // the table's own energy check failed
    std::string device = "CPU";                  // CPU or GPU
};

} // namespace app
