// Lit-sphere image helpers (see image_display.h).
#include "pipeline/image_display.h"

#include "core/color.h"

#include <algorithm>
#include <cmath>

namespace app {
namespace {
float lum(const std::vector<float>& v, size_t p) {
    return core::luminance(glm::vec3(v[3 * p], v[3 * p + 1], v[3 * p + 2]));
}
bool sameShape(const pathtrace::Image& a, const pathtrace::Image& b) {
    return a.width == b.width && a.height == b.height && a.mean.size() == b.mean.size() &&
           !a.mean.empty();
}
} // namespace

pathtrace::Image combine(const pathtrace::Image& a, const pathtrace::Image& b) {
    if (a.samples == 0 || a.mean.empty()) return b;
    if (b.samples == 0 || b.mean.empty()) return a;
    pathtrace::Image out = a;
    const double na = double(a.samples), nb = double(b.samples), n = na + nb;
    for (size_t i = 0; i < a.mean.size(); ++i) {
        out.mean[i] = float((na * a.mean[i] + nb * b.mean[i]) / n);
        out.variance[i] = float((na * na * a.variance[i] + nb * nb * b.variance[i]) / (n * n));
    }
    out.samples = a.samples + b.samples;
    return out;
}

std::vector<uint8_t> tonemap(const pathtrace::Image& img, float exposure, float gamma) {
    const size_t n = size_t(img.width) * size_t(img.height);
    std::vector<uint8_t> out(n * 4, 255);
    if (img.mean.size() < n * 3) return out;
    const float k = std::exp2(exposure), inv = 1.0f / std::max(gamma, 0.05f);
    for (size_t p = 0; p < n; ++p) {
        bool invalid = false;
        for (int c = 0; c < 3; ++c) {
            const float m = img.mean[3 * p + c];
            if (!std::isfinite(m)) { // (a NaN would pass std::max and std::clamp unchanged)
                invalid = true;
                continue;
            }
            const float v = std::pow(std::max(m * k, 0.0f), inv);
            out[4 * p + c] = uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
        }
        if (invalid) out[4 * p] = 255, out[4 * p + 1] = 0, out[4 * p + 2] = 255;
    }
    return out;
}

void paintMisses(std::vector<uint8_t>& rgba, const std::vector<glm::vec4>& hits,
                 glm::vec3 background) {
    if (rgba.size() != 4 * hits.size()) return;
    uint8_t bg[3];
    for (int c = 0; c < 3; ++c) // as the GPU stores a display value into RGBA8
        bg[c] = uint8_t(std::clamp(background[c], 0.0f, 1.0f) * 255.0f + 0.5f);
    for (size_t p = 0; p < hits.size(); ++p)
        if (!(hits[p].w >= 0.5f)) {
            for (int c = 0; c < 3; ++c)
                rgba[4 * p + size_t(c)] = bg[c];
            rgba[4 * p + 3] = 255;
        }
}

std::array<uint8_t, 3> divergingColor(float t) {
    if (std::isnan(t)) return {255, 0, 255}; // magenta, as the images show a NaN
    t = std::clamp(t, -1.0f, 1.0f);
    const float a = std::abs(t);
    if (t >= 0) return {uint8_t(255 * a), uint8_t(60 * a), uint8_t(40 * a)};
    return {uint8_t(40 * a), uint8_t(110 * a), uint8_t(255 * a)};
}

std::array<uint8_t, 3> sequentialColor(float t) {
    // five stops from dark violet through teal to yellow: monotone in lightness, so a log
    // scale reads the same in grey print
    static const float kStops[5][3] = {
        {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    t = std::clamp(std::isfinite(t) ? t : 0.0f, 0.0f, 1.0f) * 4.0f;
    const int i = std::min(int(t), 3);
    const float f = t - float(i);
    std::array<uint8_t, 3> c;
    for (int k = 0; k < 3; ++k)
        c[size_t(k)] = uint8_t(kStops[i][k] + f * (kStops[i + 1][k] - kStops[i][k]) + 0.5f);
    return c;
}

std::vector<uint8_t> differenceMap(const pathtrace::Image& a, const pathtrace::Image& b,
                                   float range) {
    const size_t n = size_t(a.width) * size_t(a.height);
    std::vector<uint8_t> out(n * 4, 255);
    if (!sameShape(a, b)) return out;
    for (size_t p = 0; p < n; ++p) {
        const float d = (lum(a.mean, p) - lum(b.mean, p)) / std::max(range, 1e-30f);
        auto c = divergingColor(d);
        out[4 * p] = c[0];
        out[4 * p + 1] = c[1];
        out[4 * p + 2] = c[2];
    }
    return out;
}

float maxAbsDifference(const pathtrace::Image& a, const pathtrace::Image& b) {
    if (!sameShape(a, b)) return 0;
    float m = 0;
    for (size_t p = 0; p < a.mean.size() / 3; ++p)
        m = std::max(m, std::abs(lum(a.mean, p) - lum(b.mean, p)));
    return m;
}

namespace {
float lumVar(const std::vector<float>& v, size_t p) {
    float s = 0;
    for (int c = 0; c < 3; ++c)
        s += float(core::kRec709Luminance[c] * core::kRec709Luminance[c]) *
             std::max(v[3 * p + size_t(c)], 0.0f);
    return s;
}
} // namespace

std::vector<uint8_t> zMap(const pathtrace::Image& a, const pathtrace::Image& b, float zRange) {
    const size_t n = size_t(a.width) * size_t(a.height);
    std::vector<uint8_t> out(n * 4, 255);
    if (!sameShape(a, b) || a.variance.size() != a.mean.size() ||
        b.variance.size() != b.mean.size())
        return out;
    for (size_t p = 0; p < n; ++p) {
        const float d = lum(a.mean, p) - lum(b.mean, p);
        const float var = lumVar(a.variance, p) + lumVar(b.variance, p);
        std::array<uint8_t, 3> c;
        if (d == 0 && var == 0)
            c = {0, 0, 0};
        else if (!(var > 0) || !std::isfinite(d))
            c = divergingColor(std::nanf("")); // magenta
        else if (std::abs(d) < 2 * std::sqrt(var))
            c = {90, 90, 90};
        else
            c = divergingColor(d / std::sqrt(var) / std::max(zRange, 1e-6f));
        out[4 * p] = c[0];
        out[4 * p + 1] = c[1];
        out[4 * p + 2] = c[2];
    }
    return out;
}

double relativeStandardError(const pathtrace::Image& img) {
    std::vector<double> rel;
    const size_t n = img.mean.size() / 3;
    if (img.variance.size() != img.mean.size()) return std::nan("");
    for (size_t p = 0; p < n; ++p) {
        const float l = lum(img.mean, p);
        if (l > 0 && std::isfinite(l))
            rel.push_back(std::sqrt(double(lumVar(img.variance, p))) / l);
    }
    if (rel.empty()) return std::nan("");
    std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
    return rel[rel.size() / 2];
}

PixelValue pixelAt(const pathtrace::Image& img, int x, int y) {
    PixelValue v;
    if (x < 0 || y < 0 || x >= img.width || y >= img.height || img.mean.empty()) return v;
    const size_t p = size_t(y) * size_t(img.width) + size_t(x);
    v.valid = true;
    for (int c = 0; c < 3; ++c) {
        v.mean[c] = img.mean[3 * p + c];
        v.stderr_[c] = std::sqrt(std::max(img.variance[3 * p + c], 0.0f));
    }
    return v;
}

} // namespace app
