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

// Adds the fonts to the current ImGui context's atlas (before its first frame, or after
// clearing it), rasterised at `uiScale` times their size and drawn at 1/uiScale (io's
// FontGlobalScale): on a display that scales the UI by uiScale (gui.h, GuiOptions::uiScale) the
// text is as large as at 1 and as sharp as the screen's pixels. Returns false when the symbol
// font could not be merged.
bool loadFonts(float uiScale = 1.0f);

} // namespace app
