// Images of the texture-space stages (texspace_images.h).
#include "pipeline/texspace_images.h"

#include "core/color.h"
#include "pipeline/image_display.h"

#include <algorithm>
#include <cmath>

namespace app {

namespace {

// Texel (row-major, v up) → image pixel (row 0 at the top).
size_t pixelOf(int size, size_t texel) {
    const size_t i = texel % size_t(size), j = texel / size_t(size);
    return (size_t(size) - 1 - j) * size_t(size) + i;
}

void put(Rgba8Image& im, size_t pixel, uint8_t r, uint8_t g, uint8_t b) {
    im.rgba[4 * pixel] = r, im.rgba[4 * pixel + 1] = g, im.rgba[4 * pixel + 2] = b;
    im.rgba[4 * pixel + 3] = 255;
}

uint8_t byte(double v) {
    return uint8_t(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
}

Rgba8Image blank(int size) {
    Rgba8Image im;
    im.width = im.height = size;
    im.rgba.assign(size_t(size) * size_t(size) * 4, 0);
    for (size_t k = 3; k < im.rgba.size(); k += 4)
        im.rgba[k] = 255;
    return im;
}

} // namespace

Rgba8Image eprimeImage(const texspace::Pipeline& p) {
    const texspace::Texels& t = p.texels();
    Rgba8Image im = blank(t.size);
    if (t.size == 0 || !p.lightReady()) return im;
    const std::vector<glm::vec3> e = p.eprime();
    std::vector<float> y;
    for (size_t k = 0; k < e.size(); ++k)
        if (t.triangle[k] >= 0) y.push_back(core::luminance(e[k]));
    float scale = 1.0f;
    if (!y.empty()) {
        auto q = y.begin() + std::ptrdiff_t(0.99 * double(y.size() - 1));
        std::nth_element(y.begin(), q, y.end());
        if (*q > 0) scale = 1.0f / *q;
    }
    for (size_t k = 0; k < e.size(); ++k) {
        const size_t px = pixelOf(t.size, k);
        if (t.triangle[k] < 0) {
            put(im, px, 30, 34, 48);
            continue;
        }
        const glm::vec3 c = e[k] * scale;
        put(im, px, byte(std::pow(c.x, 1 / 2.2)), byte(std::pow(c.y, 1 / 2.2)),
            byte(std::pow(c.z, 1 / 2.2)));
    }
    return im;
}

Rgba8Image cdfLevelImage(const texspace::MipCdf& cdf, int level) {
    if (cdf.levels.empty()) return blank(1);
    level = std::clamp(level, 0, int(cdf.levels.size()) - 1);
    const int size = cdf.size >> level;
    const std::vector<double>& v = cdf.levels[size_t(level)];
    Rgba8Image im = blank(size);
    const double peak = *std::max_element(v.begin(), v.end());
    for (size_t k = 0; k < v.size(); ++k) {
        if (!(v[k] > 0) || !(peak > 0)) continue;
        const double t = 1.0 + std::log10(v[k] / peak) / 4.0; // four decades
        const auto c = sequentialColor(float(std::clamp(t, 0.0, 1.0)));
        put(im, pixelOf(size, k), c[0], c[1], c[2]);
    }
    return im;
}

Rgba8Image atlasImage(const texspace::Pipeline& p) {
    const texspace::Texels& t = p.texels();
    Rgba8Image im = blank(t.size);
    const texspace::Parameterization& param = p.parameterization();
    for (size_t k = 0; k < t.triangle.size(); ++k) {
        const int32_t f = t.triangle[k];
        if (f < 0) continue;
        const double s = param.stretch[size_t(f)];
        const double x = std::clamp(std::log(s) / std::log(4.0), 0.0, 1.0);
        auto c = sequentialColor(float(0.15 + 0.85 * x));
        const double shade = (f % 2) ? 1.0 : 0.8; // neighbours apart
        put(im, pixelOf(t.size, k), byte(c[0] / 255.0 * shade), byte(c[1] / 255.0 * shade),
            byte(c[2] / 255.0 * shade));
    }
    return im;
}

Rgba8Image samplesImage(const texspace::Pipeline& p, const texspace::SampleSet& set) {
    Rgba8Image im = eprimeImage(p);
    for (size_t k = 0; k < im.rgba.size(); k += 4)
        for (int c = 0; c < 3; ++c)
            im.rgba[k + size_t(c)] = uint8_t(im.rgba[k + size_t(c)] / 3);
    for (uint32_t texel : set.texel)
        put(im, pixelOf(im.width, texel), 60, 255, 90);
    return im;
}

} // namespace app
