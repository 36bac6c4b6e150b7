// irradiance/projected_texture: image loading and the checkerboard (see projected_texture.h).
#include "irradiance/projected_texture.h"

#include "core/core.h"
#include "irradiance/environment.h"

#include <stb_image.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace irradiance::detail {

float srgbToLinear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

RgbImage loadRgbImage(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    RgbImage img;
    if (ext == ".exr") {
        const EnvironmentMap e = readEnvironment(path);
        img.width = e.width;
        img.height = e.height;
        img.rgb = e.rgb;
        return img;
    }
    const std::string bytes = core::readFile(path); // names the path when missing
    int w = 0, h = 0, channels = 0;
    unsigned char* data =
        stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()),
                              static_cast<int>(bytes.size()), &w, &h, &channels, 3);
    if (!data)
        throw core::Error(path.string(), 0,
                          std::string("cannot decode image: ") + stbi_failure_reason());
    img.width = w;
    img.height = h;
    img.rgb.resize(3 * static_cast<size_t>(w) * h);
    for (size_t i = 0; i < img.rgb.size(); ++i)
        img.rgb[i] = srgbToLinear(data[i] / 255.0f);
    stbi_image_free(data);
    return img;
}

RgbImage checkerImage() {
    constexpr int kSquares = 8, kTexels = 8, n = kSquares * kTexels;
    RgbImage img;
    img.width = img.height = n;
    img.rgb.resize(3 * n * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float v = ((x / kTexels + y / kTexels) % 2 == 0) ? 1.0f : 0.25f;
            for (int c = 0; c < 3; ++c)
                img.rgb[3 * (static_cast<size_t>(y) * n + x) + c] = v;
        }
    return img;
}

} // namespace irradiance::detail
