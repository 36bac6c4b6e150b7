// The GUI's font: ImGui's built-in one (ProggyClean, which covers Latin-1 only) with the glyphs
// the panels, stage messages and reports print beyond it — Greek (σ, θ, π, Σ), dashes and
// ellipses, primes, arrows, super- and subscripts, mathematical operators and the geometric
// shapes of the tab arrows — merged from DejaVu Sans (Debian's fonts-dejavu-core, which `run`
// installs). Without that file the text still draws, those glyphs as '?', and the log says why.
#pragma once

#include <filesystem>

namespace app {

// Where DejaVu Sans is read from.
std::filesystem::path symbolFontFile();

// Adds the fonts to the current ImGui context's atlas (before its first frame). Returns false
// when the symbol font could not be merged.
bool loadFonts();

} // namespace app
