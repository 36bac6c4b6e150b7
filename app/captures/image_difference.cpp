// Images as the tables replay compares, and the pictures of a failed image stage
// (image_difference.h).
#include "captures/image_difference.h"

#include "core/color.h"
#include "gl/gl.h"
#include "pathtrace/image_io.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace app {
namespace fs = std::filesystem;

// x, y, then each channel with its standard error: the form compareStatTables reads.
capture::Table imageTable(const pathtrace::Image& img) {
    capture::Table t;
    t.columns = {"x", "y", "R", "R_stderr", "G", "G_stderr", "B", "B_stderr"};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const size_t p = size_t(y) * size_t(img.width) + size_t(x);
            std::vector<double> row{double(x), double(y)};
            for (int c = 0; c < 3; ++c) {
                row.push_back(img.mean[3 * p + c]);
                row.push_back(std::sqrt(std::max(0.0, double(img.variance[3 * p + c]))));
            }
            t.rows.push_back(std::move(row));
        }
    return t;
}

capture::Table renderTable(const pathtrace::Image& img) {
    capture::Table t;
    t.columns = {"x", "y", "R", "G", "B"};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const size_t p = size_t(y) * size_t(img.width) + size_t(x);
            t.rows.push_back(
                {double(x), double(y), img.mean[3 * p], img.mean[3 * p + 1], img.mean[3 * p + 2]});
        }
    return t;
}

std::string writeImageDifference(const fs::path& captureDir, const std::string& stage,
                                 const pathtrace::Image& recorded, const pathtrace::Image& replayed,
                                 double absTol, double relTol) {
    if (recorded.width != replayed.width || recorded.height != replayed.height)
        return "(no difference image: the sizes differ)";
    const fs::path dir = captureDir.parent_path() / (captureDir.filename().string() + ".replay");
    const int w = recorded.width, h = recorded.height;
    std::vector<unsigned char> rgba(size_t(3 * w) * size_t(h) * 4, 255);
    auto put = [&](int x, int y, glm::vec3 c) {
        unsigned char* p = &rgba[(size_t(y) * size_t(3 * w) + size_t(x)) * 4];
        for (int k = 0; k < 3; ++k)
            p[k] = (unsigned char)(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    };
    auto tone = [](float v) {
        return std::pow(std::max(v, 0.0f) / (1.0f + std::max(v, 0.0f)), 1.0f / 2.2f);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p = size_t(y) * size_t(w) + size_t(x);
            float excess = 0;
            glm::vec3 a, b;
            for (int c = 0; c < 3; ++c) {
                a[c] = recorded.mean[3 * p + size_t(c)];
                b[c] = replayed.mean[3 * p + size_t(c)];
                const double d = std::abs(double(b[c]) - double(a[c]));
                const double lim = absTol + relTol * std::abs(double(a[c]));
                excess = std::max(excess, float(lim > 0 ? d / lim : (d > 0 ? 1e9 : 0.0)));
                if (!std::isfinite(a[c]) || !std::isfinite(b[c])) excess = 1e9f;
            }
            put(x, y, {tone(a.x), tone(a.y), tone(a.z)});
            put(x + w, y, {tone(b.x), tone(b.y), tone(b.z)});
            put(x + 2 * w, y, core::colorRamp(std::min(excess, 2.0f) / 2.0f));
        }
    try {
        fs::create_directories(dir);
        const fs::path png = dir / (stage + ".diff.png"), exr = dir / (stage + ".replayed.exr");
        gl::writePng(png, 3 * w, h, rgba);
        pathtrace::writeExr(exr, replayed);
        return "recorded | replayed | difference (ramp over 0..2x tolerance): " + png.string() +
               "; replayed image: " + exr.string();
    } catch (const std::exception& e) {
        return std::string("(no difference image: ") + e.what() + ")";
    }
}

} // namespace app
