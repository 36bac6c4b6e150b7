// Pictures of the geometry scores (geometry_images.h).
#include "pipeline/geometry_images.h"

#include <algorithm>
#include <cmath>

namespace app {
namespace {

constexpr uint8_t kBackground[4] = {38, 40, 48, 255};

void put(RgbaImage& img, size_t p, double r, double g, double b) {
    const auto byte = [](double v) { return uint8_t(std::lround(255 * std::clamp(v, 0.0, 1.0))); };
    img.rgba[4 * p + 0] = byte(r);
    img.rgba[4 * p + 1] = byte(g);
    img.rgba[4 * p + 2] = byte(b);
    img.rgba[4 * p + 3] = 255;
}

RgbaImage blank(int w, int h) {
    RgbaImage img{w, h, std::vector<uint8_t>(size_t(w) * size_t(h) * 4)};
    for (size_t p = 0; p < size_t(w) * size_t(h); ++p)
        std::copy(kBackground, kBackground + 4, img.rgba.begin() + long(4 * p));
    return img;
}

// Diverging blue–white–red of t ∈ [−1, 1].
void diverging(RgbaImage& img, size_t p, double t) {
    t = std::clamp(t, -1.0, 1.0);
    if (t < 0)
        put(img, p, 1 + 0.85 * t, 1 + 0.6 * t, 1 + 0.1 * t);
    else
        put(img, p, 1 - 0.1 * t, 1 - 0.75 * t, 1 - 0.85 * t);
}

void blit(RgbaImage& dst, const RgbaImage& src, int x0, int y0) {
    for (int y = 0; y < src.height; ++y)
        std::copy(src.rgba.begin() + long(4 * size_t(y) * size_t(src.width)),
                  src.rgba.begin() + long(4 * (size_t(y) + 1) * size_t(src.width)),
                  dst.rgba.begin() + long(4 * ((size_t(y0 + y)) * size_t(dst.width) + size_t(x0))));
}

} // namespace

double whitePoint(const ChannelImage& ref) {
    std::vector<double> v;
    for (size_t p = 0; p < ref.mean.size(); ++p)
        if (ref.covered[p] && std::isfinite(ref.mean[p])) v.push_back(ref.mean[p]);
    if (v.empty()) return 1;
    const size_t k = std::min(v.size() - 1, size_t(0.99 * double(v.size())));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k] > 0 ? v[k] : 1;
}

RgbaImage toneMapped(const ChannelImage& img, double white) {
    RgbaImage out = blank(img.width, img.height);
    for (size_t p = 0; p < img.mean.size(); ++p) {
        if (!img.covered[p]) continue;
        const double v = std::pow(std::clamp(img.mean[p] / white, 0.0, 1.0), 1 / 2.2);
        put(out, p, v, v, v);
    }
    return out;
}

RgbaImage signedErrorMap(const ChannelImage& model, const ChannelImage& ref, double range) {
    RgbaImage out = blank(ref.width, ref.height);
    double sum = 0;
    size_t n = 0;
    for (size_t p = 0; p < ref.mean.size(); ++p)
        if (ref.covered[p]) sum += ref.mean[p], ++n;
    const double floor = n ? 0.05 * sum / double(n) : 0; // dark pixels: relative to 5 % of the mean
    for (size_t p = 0; p < ref.mean.size(); ++p) {
        if (!ref.covered[p] || !model.covered[p]) continue;
        const double r = std::max(ref.mean[p], floor);
        diverging(out, p, r > 0 ? (model.mean[p] - ref.mean[p]) / r / range : 0.0);
    }
    return out;
}

RgbaImage caseStrip(const ChannelImage& ref, const std::vector<const ChannelImage*>& models) {
    const int w = ref.width, h = ref.height, gap = 2;
    const int cols = 1 + int(models.size());
    RgbaImage strip{cols * w + (cols - 1) * gap, 2 * h + gap, {}};
    strip.rgba.assign(size_t(strip.width) * size_t(strip.height) * 4, 255);
    const double white = whitePoint(ref);
    blit(strip, toneMapped(ref, white), 0, 0);
    RgbaImage scale = blank(w, h); // the colour scale: −range at the left to +range at the right
    for (int y = h / 3; y < 2 * h / 3; ++y)
        for (int x = 0; x < w; ++x)
            diverging(scale, size_t(y) * size_t(w) + size_t(x), 2.0 * (x + 0.5) / w - 1);
    blit(strip, scale, 0, h + gap);
    for (size_t k = 0; k < models.size(); ++k) {
        const int x = int(k + 1) * (w + gap);
        blit(strip, toneMapped(*models[k], white), x, 0);
        blit(strip, signedErrorMap(*models[k], ref), x, h + gap);
    }
    return strip;
}

} // namespace app
