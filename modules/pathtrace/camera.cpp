// pathtrace/camera: input checks, pixel mapping, per-path tallies and their finalisation into
// an Image (estimator in camera.h).
#include "pathtrace/camera.h"
#include "core/text.h"

#include "core/core.h"
#include "pathtrace/detail/energy_check.h"
#include "pathtrace/detail/mean_stderr.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace pathtrace {
using detail::meanStderr;

void validate(const TraceOptions& o) {
    const std::string what = "trace options";
    validate(o.termination, what);
    if (o.footprintSubsamples < 1 || o.footprintSubsamples > 64)
        throw core::Error(what, 0,
                          "footprintSubsamples must lie in [1, 64], got " +
                              std::to_string(o.footprintSubsamples));
}

void validate(const LitSphereSetup& s) {
    const std::string what = "lit sphere setup";
    if (!std::isfinite(s.radiusMm) || !(s.radiusMm > 0))
        throw core::Error(what, 0,
                          "radius must be a finite length > 0 mm, got " +
                              core::formatNumber(s.radiusMm));
    const double l2 = s.lightDir[0] * s.lightDir[0] + s.lightDir[1] * s.lightDir[1] +
                      s.lightDir[2] * s.lightDir[2];
    if (!std::isfinite(l2) || !(l2 > 0))
        throw core::Error(what, 0,
                          "light direction must be finite and non-zero, got (" +
                              core::formatNumber(s.lightDir[0]) + ", " +
                              core::formatNumber(s.lightDir[1]) + ", " +
                              core::formatNumber(s.lightDir[2]) + ")");
    if (s.width < 1 || s.width > 16384 || s.height < 1 || s.height > 16384)
        throw core::Error(what, 0,
                          "image size must lie in [1, 16384]², got " + std::to_string(s.width) +
                              "x" + std::to_string(s.height));
    if (s.samplesPerPixel < 1 || s.samplesPerPixel > 10000000)
        throw core::Error(what, 0,
                          "samples per pixel must lie in [1, 10^7], got " +
                              std::to_string(s.samplesPerPixel));
    if (s.threads < 0)
        throw core::Error(what, 0,
                          "threads must be >= 0 (0: all hardware threads), got " +
                              std::to_string(s.threads));
}

std::array<double, 3> unitLight(const LitSphereSetup& s) {
    const double n = std::sqrt(s.lightDir[0] * s.lightDir[0] + s.lightDir[1] * s.lightDir[1] +
                               s.lightDir[2] * s.lightDir[2]);
    return {s.lightDir[0] / n, s.lightDir[1] / n, s.lightDir[2] / n};
}

OrthoCamera::OrthoCamera(const LitSphereSetup& s, double radius)
    : width(s.width), height(s.height), extent(1.1 * radius), dx(2.0 * extent / s.width),
      dy(2.0 * extent / s.height) {}

int OrthoCamera::pixelOf(double x, double y) const {
    const double fi = (x + extent) / dx, fj = (extent - y) / dy;
    if (!(fi >= 0 && fj >= 0)) return -1;
    const int i = static_cast<int>(fi), j = static_cast<int>(fj);
    if (i >= width || j >= height) return -1;
    return j * width + i;
}

ImageTally::ImageTally(size_t pixels) {
    for (auto& c : channel) {
        c.pixSum.assign(pixels, 0.0);
        c.pixSumSq.assign(pixels, 0.0);
    }
}

void ImageTally::add(const ExitRecord* rec, uint64_t count, uint64_t i) {
    ++paths;
    for (int c = 0; c < kChannels; ++c) {
        const ExitRecord& r = rec[static_cast<uint64_t>(c) * count + i];
        ChannelTally& t = channel[static_cast<size_t>(c)];
        t.hitSum += r.hit;
        t.specSum += r.specular;
        t.specSumSq += r.specular * r.specular;
        t.exitSum += r.exited;
        t.exitSumSq += r.exited * r.exited;
        t.absSum += r.absorbed;
        t.absSumSq += r.absorbed * r.absorbed;
        t.rouletteSum += r.rouletteLoss;
        t.rouletteSumSq += r.rouletteLoss * r.rouletteLoss;
        t.leakSum += r.leaked;
        if (r.truncated != 0) {
            t.truncSum += r.truncated;
            t.truncSumSq += r.truncated * r.truncated;
            ++t.truncatedPaths;
        }
        t.leaks += r.leaked != 0 ? 1 : 0;
        t.events += r.events;
        if (r.pixel >= 0 && static_cast<size_t>(r.pixel) < t.pixSum.size()) {
            t.pixSum[static_cast<size_t>(r.pixel)] += r.exited;
            t.pixSumSq[static_cast<size_t>(r.pixel)] += r.exited * r.exited;
        }
    }
}

Image finalizeImage(const ImageTally& t, const PixelGeometry& px, int width, int height,
                    double sourceArea, double areaToMm2, ImageStats* stats) {
    Image img;
    img.width = width;
    img.height = height;
    img.samples = t.paths;
    const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
    img.mean.assign(3 * n, 0.0f);
    img.variance.assign(3 * n, 0.0f);
    for (int c = 0; c < kChannels; ++c) {
        const ChannelTally& ct = t.channel[static_cast<size_t>(c)];
        for (size_t p = 0; p < n; ++p) {
            const double area = px.footprint[p];
            if (!(area > 0)) continue; // centre ray misses: 0, variance 0
            double mean, err;
            meanStderr(ct.pixSum[p], ct.pixSumSq[p], t.paths, sourceArea / area, mean, err);
            img.mean[3 * p + static_cast<size_t>(c)] = static_cast<float>(mean);
            img.variance[3 * p + static_cast<size_t>(c)] = static_cast<float>(err * err);
        }
    }
    if (stats) {
        const double srcMm2 = sourceArea * areaToMm2;
        stats->paths = t.paths;
        stats->sourceAreaMm2 = srcMm2;
        double incident = 0;
        for (int c = 0; c < kChannels; ++c) {
            const ChannelTally& ct = t.channel[static_cast<size_t>(c)];
            ChannelStats& s = stats->channel[static_cast<size_t>(c)];
            // hit ∈ {0, 1}: Σhit² = Σhit.
            meanStderr(ct.hitSum, ct.hitSum, t.paths, srcMm2, s.incident, s.incidentStderr);
            meanStderr(ct.specSum, ct.specSumSq, t.paths, srcMm2, s.specular, s.specularStderr);
            meanStderr(ct.exitSum, ct.exitSumSq, t.paths, srcMm2, s.exited, s.exitedStderr);
            meanStderr(ct.absSum, ct.absSumSq, t.paths, srcMm2, s.absorbed, s.absorbedStderr);
            meanStderr(ct.rouletteSum, ct.rouletteSumSq, t.paths, srcMm2, s.rouletteNet,
                       s.rouletteNetStderr);
            meanStderr(ct.truncSum, ct.truncSumSq, t.paths, srcMm2, s.truncated, s.truncatedStderr);
            s.truncatedPaths = ct.truncatedPaths;
            s.leaked = t.paths ? srcMm2 * ct.leakSum / static_cast<double>(t.paths) : 0;
            s.leaks = ct.leaks;
            s.events = ct.events;
            incident += s.incident / kChannels;
        }
        stats->incidentPowerW = incident;
        stats->pixels.footprint.resize(n);
        for (size_t p = 0; p < n; ++p)
            stats->pixels.footprint[p] = px.footprint[p] * areaToMm2;
        stats->pixels.cosLight = px.cosLight;
    }
    return img;
}

std::string energyProblem(const ChannelStats& s) {
    return detail::energyProblem(
        {"specular + exited + absorbed + truncated + roulette + leaked",
         s.specular + s.exited + s.absorbed + s.truncated + s.rouletteNet + s.leaked, s.incident,
         s.rouletteNet, s.rouletteNetStderr, s.truncated, s.exitedStderr, s.truncatedPaths,
         "the exited power", " W"});
}

} // namespace pathtrace
