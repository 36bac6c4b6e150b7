// bench pathtrace --mcml: MCML 1.2.2 (Wang, Jacques & Zheng 1995), built by the user from its
// sources, timed on this machine on the bench's case as the CPU peer of our tracer. One MCML
// process runs `batches` runs of the same input back to back (an .mci with that many runs): its
// generator continues from run to run, so the runs are independent batches. The spread of their
// R_d(r) gives MCML's variance per photon in each bin, the wall time its photons per second
// (start-up included; a few ms against seconds), so its time to 1 % comes from this run only.
#include "bench/mcml_peer.h"

#include "core/core.h"
#include "core/text.h"
#include "pathtrace/mco.h"
#include "probe/child_process.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <thread>

#include <unistd.h>

namespace app {

namespace {

// The .mci of `batches` runs of one semi-infinite layer (MCML units: cm, 1/cm).
std::string mciText(const pathtrace::Medium& m, const McmlCase& c,
                    const std::filesystem::path& dir) {
    const double mua = m.sigmaA * 10, mus = m.sigmaS * 10;
    const double thickness = std::max(100.0, 2000.0 / (mua + mus)); // > 1000 mean free paths
    std::ostringstream o;
    o << "1.0\n" << c.batches << "\n";
    for (int i = 0; i < c.batches; ++i) {
        o << (dir / ("run" + std::to_string(i) + ".mco")).string() << " A\n"
          << c.photonsPerBatch << "\n"
          << core::formatNumber(thickness) << " " << core::formatNumber(c.binMm / 10) << "\n"
          << "1 " << c.bins << " 1\n"
          << "1\n1.0\n"
          << core::formatNumber(m.eta) << " " << core::formatNumber(mua) << " "
          << core::formatNumber(mus) << " " << core::formatNumber(m.g) << " "
          << core::formatNumber(thickness) << "\n1.0\n";
    }
    return o.str();
}

} // namespace

McmlPeer runMcmlPeer(const std::filesystem::path& exe, const pathtrace::Medium& m,
                     const McmlCase& c) {
    if (!std::filesystem::is_regular_file(exe))
        throw core::Error(exe.string(), 0, "--mcml: no such executable (MCML 1.2.2's `mcml`)");
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("bw-mcml-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    struct Cleanup {
        std::filesystem::path d;
        ~Cleanup() {
            std::error_code ec;
            std::filesystem::remove_all(d, ec);
        }
    } cleanup{dir};
    const std::filesystem::path mci = dir / "case.mci";
    core::writeFile(mci, mciText(m, c, dir));

    ChildProcess child({std::filesystem::absolute(exe).string(), mci.string()}, "--mcml");
    core::Stopwatch clock;
    while (!child.poll())
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    McmlPeer p;
    p.seconds = clock.ms() / 1000.0;
    if (child.exitCode() != 0)
        throw core::Error(exe.string(), 0,
                          "--mcml: exit status " + std::to_string(child.exitCode()) + ": " +
                              child.output().substr(0, 400));
    std::vector<std::vector<double>> rd; // per batch, per bin (1/cm²; the scale cancels)
    for (int i = 0; i < c.batches; ++i) {
        const auto f = dir / ("run" + std::to_string(i) + ".mco");
        if (!std::filesystem::exists(f))
            throw core::Error(f.string(), 0, "--mcml: MCML wrote no output (is it MCML 1.2.2?)");
        rd.push_back(pathtrace::readMco(f).rdR);
        if (int(rd.back().size()) != c.bins)
            throw core::Error(f.string(), 0, "--mcml: unexpected number of radial bins");
    }
    p.photons = double(c.photonsPerBatch) * c.batches;
    p.photonsPerSecond = p.photons / std::max(p.seconds, 1e-9);
    // Relative variance per photon of bin b: n_batch · Var(batch means) / mean².
    auto relVar = [&](int b) {
        double mean = 0, sq = 0;
        for (const auto& r : rd)
            mean += r[size_t(b)] / c.batches;
        for (const auto& r : rd)
            sq += (r[size_t(b)] - mean) * (r[size_t(b)] - mean);
        const double var = sq / (c.batches - 1);
        return mean > 0 ? double(c.photonsPerBatch) * var / (mean * mean) : INFINITY;
    };
    p.relVar.resize(size_t(c.bins));
    for (int b = 0; b < c.bins; ++b)
        p.relVar[size_t(b)] = relVar(b);
    return p;
}

} // namespace app
