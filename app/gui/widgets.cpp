// Helpers shared by the scene panels (widgets.h).
#include "gui/widgets.h"

#include "plot/plot_draw.h"

#include <imgui_internal.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>
#include <unordered_map>

namespace app {

void samplingChoice(const char* label, integrate::Sampling& s, sampling::AxisScheme& axes) {
    int v = static_cast<int>(s);
    setItemWidth(170, label);
    if (ImGui::Combo(label, &v, "uniform area\0disk probe rays\0"))
        s = static_cast<integrate::Sampling>(v);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("uniform: entry points uniform on the surface (thesis 3.5)\ndisk: probe "
                          "rays through disks around the shading point, radius importance-sampled "
                          "from the model's own profile, MIS over three axes and the channels "
                          "(King et al. 2013)");
    if (s != integrate::Sampling::Disk) return;
    int a = static_cast<int>(axes);
    sameLineItem(150, "axes");
    if (ImGui::Combo("axes", &a,
                     "N, T, B: 1/3 each\0N 1/2, T, B 1/4\0N only\0N 2, T 1, B 1 per sample\0"))
        axes = static_cast<sampling::AxisScheme>(a);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", integrate::kAxesHelp);
}

void ensureInspectCamera(Workbench& wb, UiShared& ui) {
    if (ui.inspect.cameraSet || !wb.scene().hasMesh()) return;
    ui.inspect.camera = wb.scene().settings().render.camera;
    ui.inspect.camera.fit(wb.scene().mesh());
    ui.inspect.camera.yaw = wb.scene().settings().render.camera.yaw;
    ui.inspect.camera.pitch = wb.scene().settings().render.camera.pitch;
    ui.inspect.cameraSet = true;
}

Rect lastItem() {
    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    return {lo.x, lo.y, hi.x, hi.y};
}

namespace {
// The right edge of what the window shows (its content region grows with horizontal scrolling,
// so once something ran over, widths and wraps relative to it would keep it running over).
float visibleRight() {
    const ImGuiStyle& st = ImGui::GetStyle();
    return ImGui::GetWindowPos().x + ImGui::GetWindowWidth() - st.WindowPadding.x -
           st.ScrollbarSize;
}
} // namespace

float visibleWidth() {
    return visibleRight() - ImGui::GetCursorScreenPos().x;
}

void sameLineIfFits(float width) {
    if (ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + width <= visibleRight())
        ImGui::SameLine();
}

float fittingWidth(float width, const char* label) {
    const float room = visibleWidth() - itemWidth(0, label);
    return std::max(std::min(width, room), ImGui::GetFontSize() * 4);
}

void setItemWidth(float width, const char* label) {
    ImGui::SetNextItemWidth(fittingWidth(width, label));
}

void sameLineItem(float width, const char* label) {
    sameLineIfFits(itemWidth(width, label));
    setItemWidth(width, label);
}

std::string cutToWidth(std::string text, float width) {
    return plot::elided(std::move(text), width); // the plot's titles are cut the same way
}

std::string breakLines(const std::string& text, float width) {
    auto fits = [&](const std::string& s) { return ImGui::CalcTextSize(s.c_str()).x <= width; };
    std::string out;
    // a line still too wide holds one long word: cut it where it runs over
    auto emit = [&](std::string line) {
        while (!fits(line) && line.size() > 1) {
            size_t n = 1;
            while (n < line.size() && fits(line.substr(0, n + 1)))
                ++n;
            out += line.substr(0, n) + '\n';
            line.erase(0, n);
        }
        out += line;
    };
    for (size_t start = 0;;) {
        const size_t newline = std::min(text.find('\n', start), text.size());
        const std::string paragraph = text.substr(start, newline - start);
        std::string line;
        bool fresh = true, broken = false; // nothing on the line yet; a break began it
        for (size_t i = 0; i <= paragraph.size();) {
            const size_t end = std::min(paragraph.find(' ', i), paragraph.size());
            const std::string word = paragraph.substr(i, end - i); // empty: one more space
            i = end + 1;
            if (fresh) {
                if (broken && word.empty()) continue; // the spaces at a break
                line = word;
                fresh = false;
            } else if (fits(line + " " + word)) {
                line += " " + word;
            } else {
                while (!line.empty() && line.back() == ' ')
                    line.pop_back();
                emit(line);
                out += '\n';
                line = word;
                broken = true;
                fresh = word.empty();
            }
        }
        emit(line);
        if (newline >= text.size()) return out;
        out += '\n';
        start = newline + 1;
    }
}

namespace {
void wrappedTextV(const char* fmt, va_list args) {
    va_list copy;
    va_copy(copy, args);
    const int n = std::vsnprintf(nullptr, 0, fmt, copy);
    va_end(copy);
    std::string text(size_t(std::max(n, 0)) + 1, '\0');
    std::vsnprintf(text.data(), text.size(), fmt, args);
    text.resize(size_t(std::max(n, 0)));
    const float width = std::max(visibleWidth(), ImGui::GetFontSize() * 4);
    ImGui::TextUnformatted(breakLines(text, width).c_str());
}
} // namespace

void wrappedText(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    wrappedTextV(fmt, args);
    va_end(args);
}

namespace {
void colouredTextV(const ImVec4& colour, const char* fmt, va_list args) {
    ImGui::PushStyleColor(ImGuiCol_Text, colour);
    wrappedTextV(fmt, args);
    ImGui::PopStyleColor();
}
} // namespace

void colouredText(const ImVec4& colour, const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    colouredTextV(colour, fmt, args);
    va_end(args);
}

void hintText(const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    colouredTextV(ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled), fmt, args);
    va_end(args);
}

float checkboxWidth(const char* label) {
    const ImGuiStyle& st = ImGui::GetStyle();
    return ImGui::GetFrameHeight() + st.ItemInnerSpacing.x +
           ImGui::CalcTextSize(label, nullptr, true).x;
}

namespace {
// Values typed into integer fields and not yet committed, by widget ID (ImGui keeps the text
// of the active field itself; this keeps the parsed value until the field lets go).
std::unordered_map<ImGuiID, std::array<int, 2>>& pendingInts() {
    static std::unordered_map<ImGuiID, std::array<int, 2>> pending;
    return pending;
}

template <int N, class Edit> bool committedInts(const char* label, int* v, Edit edit) {
    auto& pending = pendingInts();
    // (ImGui 1.86's GetID would mark the ID alive and break the field's group bookkeeping)
    const ImGuiID id = ImGui::GetCurrentWindow()->GetIDNoKeepAlive(label);
    const auto it = pending.find(id);
    std::array<int, 2> shown{v[0], N > 1 ? v[N - 1] : 0};
    if (it != pending.end()) shown = it->second;
    const bool changed = edit(shown.data());
    const bool typing = ImGui::IsItemActive() && ImGui::GetIO().WantTextInput;
    if (changed && typing) {
        pending[id] = shown; // wait for Enter or focus loss
        return false;
    }
    if (changed || (it != pending.end() && !ImGui::IsItemActive())) {
        for (int i = 0; i < N; ++i)
            v[i] = shown[size_t(i)];
        pending.erase(id);
        return true;
    }
    return false;
}
} // namespace

bool inputIntCommitted(const char* label, int* v, int step, int stepFast) {
    return committedInts<1>(label, v,
                            [&](int* x) { return ImGui::InputInt(label, x, step, stepFast); });
}

bool exitSamplesInput(int& samples) {
    sameLineItem(90, "exit samples");
    const bool changed = inputIntCommitted("exit samples", &samples);
    if (changed) samples = std::clamp(samples, 0, 64);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("expected-value exits (CPU analog and implicit walks): each collision "
                          "near the surface\nscores this many directions with their probability "
                          "of leaving, where they would leave;\n0: the exits that happen "
                          "(thesis Algorithm 1). Same expectation, less noise per path.");
    return changed;
}

bool inputInt2Committed(const char* label, int v[2]) {
    return committedInts<2>(label, v, [&](int* x) { return ImGui::InputInt2(label, x); });
}

bool inputTextCommitted(const char* label, char* buffer, size_t size) {
    ImGui::InputText(label, buffer, size);
    // Enter on an unchanged text commits too (it reads the named file again).
    const bool enter = ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Enter), false) ||
                       ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_KeyPadEnter), false);
    return ImGui::IsItemDeactivatedAfterEdit() || (ImGui::IsItemDeactivated() && enter);
}

bool pathFieldCommitted(const char* label, char* buffer, size_t size, std::string& value) {
    // the value the field last showed, by its hash, kept in the window's storage under an ID
    // of its own (a frame's edit in progress is not the value's change)
    ImGuiStorage* storage = ImGui::GetStateStorage();
    const ImGuiID shown = ImGui::GetID((std::string(label) + "##shown").c_str());
    const int hash = int(ImHashStr(value.c_str())) | 1; // never 0, the storage's "none"
    if (storage->GetInt(shown, 0) != hash) {
        std::snprintf(buffer, size, "%s", value.c_str());
        storage->SetInt(shown, hash);
    }
    if (!inputTextCommitted(label, buffer, size)) return false;
    value = buffer;
    storage->SetInt(shown, int(ImHashStr(value.c_str())) | 1);
    return true;
}

void histogram(const char* id, const std::vector<float>& values, ImVec2 size, const char* xName,
               int xFirst, const char* yName) {
    float hi = 0;
    for (float v : values)
        hi = std::max(hi, v);
    ImGui::BeginGroup();
    ImGui::PushID(id);
    ImGui::TextDisabled("%s, max %.0f", yName, hi);
    ImGui::PlotHistogram("##bars", values.data(), int(values.size()), 0, nullptr, 0.0f,
                         hi > 0 ? hi : 1.0f, size);
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    const int n = int(values.size());
    if (ImGui::IsItemHovered() && n > 0) {
        const int i =
            std::clamp(int((ImGui::GetMousePos().x - a.x) / (b.x - a.x) * float(n)), 0, n - 1);
        ImGui::SetTooltip("%s %d: %.0f", xName, xFirst + i, double(values[size_t(i)]));
    }
    // x axis: the first and last bin under their bars, the name between
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImU32 col = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    const float barW = n > 0 ? (b.x - a.x) / float(n) : 0.0f;
    const std::string first = std::to_string(xFirst), last = std::to_string(xFirst + n - 1);
    dl->AddText(ImVec2(a.x + 0.5f * barW - 0.5f * ImGui::CalcTextSize(first.c_str()).x, b.y), col,
                first.c_str());
    if (n > 1)
        dl->AddText(ImVec2(b.x - 0.5f * barW - 0.5f * ImGui::CalcTextSize(last.c_str()).x, b.y),
                    col, last.c_str());
    dl->AddText(ImVec2(0.5f * (a.x + b.x) - 0.5f * ImGui::CalcTextSize(xName).x, b.y), col, xName);
    ImGui::Dummy(ImVec2(size.x, ImGui::GetTextLineHeight()));
    ImGui::PopID();
    ImGui::EndGroup();
}

float buttonWidth(const char* label) {
    return ImGui::CalcTextSize(label, nullptr, true).x + 2 * ImGui::GetStyle().FramePadding.x;
}

float itemWidth(float frame, const char* label) {
    const float text = ImGui::CalcTextSize(label, nullptr, true).x;
    return frame + (text > 0 ? ImGui::GetStyle().ItemInnerSpacing.x + text : 0.0f);
}

bool pickImage(const char* id, GLuint tex, int w, int h, float width, int& px, int& py, bool flipY,
               ImVec2* drag, float* wheel, ImVec2* uv) {
    if (!tex || w <= 0 || h <= 0) {
        ImGui::Dummy(ImVec2(width, width * 0.5f));
        return false;
    }
    const float height = width * float(h) / float(w);
    const ImVec2 pos = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex)), ImVec2(width, height),
                 flipY ? ImVec2(0, 1) : ImVec2(0, 0), flipY ? ImVec2(1, 0) : ImVec2(1, 1));
    // An invisible button over the image gives it an ID, so it can be dragged and clicked.
    ImGui::SetCursorScreenPos(pos);
    ImGui::InvisibleButton(id, ImVec2(width, height));
    const bool hovered = ImGui::IsItemHovered();
    if (drag) {
        *drag = ImVec2(0, 0);
        if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f)) {
            *drag = ImGui::GetIO().MouseDelta;
        }
    }
    if (wheel) *wheel = hovered ? ImGui::GetIO().MouseWheel : 0.0f;
    const ImVec2 dragged = ImGui::GetMouseDragDelta(ImGuiMouseButton_Left, 0.0f);
    if (ImGui::IsItemDeactivated() && dragged.x * dragged.x + dragged.y * dragged.y < 9.0f) {
        const ImVec2 m = ImGui::GetMousePos();
        const float u = std::clamp((m.x - pos.x) / width, 0.0f, 1.0f);
        const float v = std::clamp((m.y - pos.y) / height, 0.0f, 1.0f);
        px = std::clamp(int(u * float(w)), 0, w - 1);
        py = std::clamp(int(v * float(h)), 0, h - 1);
        if (uv) *uv = ImVec2(u, v);
        return true;
    }
    return false;
}

bool inspectorImage(Workbench& wb, UiShared& ui, SceneView& view, ImVec2 size, float pointSize,
                    float& px, float& py) {
    ensureInspectCamera(wb, ui);
    render::Camera& cam = ui.inspect.camera;
    const int w = std::max(16, int(size.x)), h = std::max(16, int(size.y));
    cam.aspect = float(w) / float(h);
    // drawn at the screen's pixels (the UI scale's per unit: sharp on a 4K screen at 200 %)
    const float scale = std::max(1.0f, ImGui::GetIO().DisplayFramebufferScale.x);
    const int tw = int(std::lround(w * scale)), th = int(std::lround(h * scale));
    view.draw(tw, th, cam.projection() * cam.view(), pointSize * scale);
    int ix = -1, iy = -1;
    ImVec2 drag;
    float wheel = 0;
    const bool clicked =
        pickImage("##inspector", view.texture(), tw, th, float(w), ix, iy, true, &drag, &wheel);
    if (drag.x != 0 || drag.y != 0) {
        cam.yaw -= drag.x * 0.01f;
        cam.pitch = std::clamp(cam.pitch + drag.y * 0.01f, -1.5f, 1.5f);
    }
    if (wheel != 0) cam.distance = std::max(0.05f, cam.distance * std::pow(0.9f, wheel));
    px = (float(ix) + 0.5f) / scale; // in UI units, as `size`
    py = (float(iy) + 0.5f) / scale;
    return clicked;
}

void rampBar(float lo, float hi, const char* unit) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float w = 220, h = 10;
    for (int i = 0; i < 44; ++i) {
        const glm::vec3 c = core::colorRamp((float(i) + 0.5f) / 44.0f);
        dl->AddRectFilled(ImVec2(p.x + w * float(i) / 44, p.y),
                          ImVec2(p.x + w * float(i + 1) / 44, p.y + h),
                          IM_COL32(int(c.x * 255), int(c.y * 255), int(c.z * 255), 255));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::Text("%.4g  ..  %.4g %s", lo, hi, unit);
}

} // namespace app
