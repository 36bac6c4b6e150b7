// pathtrace/image_io: Image (lit_sphere.h) as OpenEXR files: scanline, ZIP (lossless), FLOAT
//   channels R, G, B (per-pixel mean) and varR, varG, varB (variance of the mean), data window
//   [0, width−1] × [0, height−1], row 0 at the top; the sample count in the string attribute
//   "bw.samples". Written to memory and then atomically to disk (core::writeFile), read from
//   memory (core::readFile), so file errors name the path. Round trips are bitwise exact.
#pragma once

#include "pathtrace/lit_sphere.h"

#include <filesystem>

namespace pathtrace {

// Throws core::Error(path, 0, ...) when the image is inconsistent (sizes) or the file cannot
// be written.
void writeExr(const std::filesystem::path& path, const Image& img);
// Reads R, G, B (required; HALF or FLOAT) and varR, varG, varB (optional, 0 when absent).
// Throws core::Error(path, 0, ...) when the file is missing, not an EXR, or lacks R, G or B.
Image readExr(const std::filesystem::path& path);

} // namespace pathtrace
