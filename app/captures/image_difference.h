// Images on replay: as the tables the capture comparisons read (capture/capture.h), and, for an
// image stage that failed, pictures of the failure beside the capture.
#pragma once

#include "capture/capture.h"
#include "pathtrace/lit_sphere.h"

#include <filesystem>
#include <string>

namespace app {

// x, y, then each channel with its standard error: the form compareStatTables reads
// (kind exr_stat).
capture::Table imageTable(const pathtrace::Image& img);
// x, y, R, G, B per pixel: the form compareTables reads (kind exr).
capture::Table renderTable(const pathtrace::Image& img);

// A failed image stage leaves pictures of the failure beside the capture, in
// <capture>.replay/: the replayed image (EXR) and a PNG of recorded | replayed | difference,
// the difference as each pixel's worst |a − b| / (absTol + relTol·|b|) on the colour ramp
// over [0, 2] (above 1: out of tolerance), the images tone-mapped alike. Returns the line that
// names them, or why they could not be written (the replay result stands either way).
std::string writeImageDifference(const std::filesystem::path& captureDir, const std::string& stage,
                                 const pathtrace::Image& recorded, const pathtrace::Image& replayed,
                                 double absTol, double relTol);

} // namespace app
