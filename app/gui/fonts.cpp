// The GUI's font with the symbol glyphs merged in (fonts.h).
#include "gui/fonts.h"

#include "core/core.h"

#include <imgui.h>

namespace app {

std::filesystem::path symbolFontFile() {
    return "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

bool loadFonts(float uiScale) {
    ImGuiIO& io = ImGui::GetIO();
    const float size = 13.0f * uiScale; // ImGui's default font size, in the screen's pixels
    ImFontConfig base;
    base.SizePixels = size;
    io.Fonts->AddFontDefault(&base);
    io.FontGlobalScale = 1.0f / uiScale;
    // beyond Latin-1: the ranges the program's text uses (ImGui keeps a pointer: static)
    static const ImWchar kRanges[] = {
        0x0370, 0x03FF, // Greek
        0x2000, 0x206F, // general punctuation: — … ′ ″ •
        0x2070, 0x209F, // superscripts and subscripts
        0x2190, 0x21FF, // arrows
        0x2200, 0x22FF, // mathematical operators: ∫ √ ∞ ≈ ≤ ∂ ∑
        0x25A0, 0x25FF, // geometric shapes: ◀ ▶ ■
        0,
    };
    const std::filesystem::path file = symbolFontFile();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
        core::logWarn(file.string() + ": not found (Debian package fonts-dejavu-core); Greek "
                                      "letters and symbols show as '?'");
        return false;
    }
    ImFontConfig merge;
    merge.MergeMode = true;
    merge.PixelSnapH = true;
    return io.Fonts->AddFontFromFileTTF(file.c_str(), size, &merge, kRanges) != nullptr;
}

} // namespace app
