// irradiance/projected_texture: the RGB image of the Filtered light mode (a texture projected
// along the light, thesis 3.3.2 "filtered" directional light): loading (stb_image for PNG/JPG,
// 8-bit sRGB decoded to linear; OpenEXR R, G, B) and the default checkerboard.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace irradiance::detail {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<float> rgb; // row 0 at the top
};

// Throws core::Error(path, 0, ...) when the file is missing or cannot be decoded, or (EXR) lacks
// R, G or B or holds non-finite or negative values.
RgbImage loadRgbImage(const std::filesystem::path& path);
// 8 × 8 squares of 8 texels, 1 and 0.25 alternating, the top-left square 1.
RgbImage checkerImage();
// sRGB transfer function (IEC 61966-2-1) to linear.
float srgbToLinear(float c);

} // namespace irradiance::detail
