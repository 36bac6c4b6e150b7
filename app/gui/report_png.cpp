// Headless pictures for reports (report_png.h).
#include "gui/report_png.h"
#include "gui/imgui_render.h"

#include "core/core.h"
#include "gl/gl.h"
#include "gui/fonts.h"
#include "plot/plot_draw.h"

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

namespace app {

std::string renderImGuiPng(int width, int height, const std::function<void()>& draw) {
    if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
        throw core::Error("report", 0, "image size out of range");
    ImGuiContext* previous = ImGui::GetCurrentContext();
    ImGuiContext* own = ImGui::CreateContext();
    ImGui::SetCurrentContext(own);
    std::vector<unsigned char> px;
    {
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = ImVec2(float(width), float(height));
        io.DisplayFramebufferScale = ImVec2(1, 1);
        io.DeltaTime = 1.0f / 60.0f;
        ImGui::StyleColorsDark();
        ImGui::GetStyle().WindowRounding = 0.0f;
        ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 1.0f;
        loadFonts();
        ImGui_ImplOpenGL3_Init("#version 450");
        gl::RenderTarget target;
        target.resize(width, height);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(io.DisplaySize);
        ImGui::Begin("##report", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoScrollbar);
        draw();
        ImGui::End();
        ImGui::Render();
        target.bind();
        glViewport(0, 0, width, height);
        glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        renderImGuiDrawData();
        glFinish();
        px = gl::readPixelsRGBA8(target.framebuffer(), 0, 0, width, height);
        ImGui_ImplOpenGL3_Shutdown();
    }
    ImGui::DestroyContext(own);
    ImGui::SetCurrentContext(previous);
    for (size_t i = 3; i < px.size(); i += 4)
        px[i] = 255;
    std::string png = gl::encodePng(width, height, px);
    if (png.empty()) throw core::Error("report", 0, "cannot encode a PNG");
    return png;
}

std::string plotPng(int width, int height, const std::vector<plot::Series>& series,
                    const plot::Axis& x, const plot::Axis& y, const std::string& title,
                    const std::string& subtitle) {
    return renderImGuiPng(width, height, [&] {
        plot::PlotOptions o;
        o.hoverTooltip = false;
        plot::drawPlot("##plot", ImVec2(-1, -1), series, x, y, title, subtitle, o);
    });
}

std::string base64(const std::string& bytes) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16 |
                           unsigned(uint8_t(bytes[i + 1])) << 8 | unsigned(uint8_t(bytes[i + 2]));
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += k[v >> 6 & 63];
        out += k[v & 63];
    }
    if (i + 1 == bytes.size()) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16;
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += "==";
    } else if (i + 2 == bytes.size()) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16 | unsigned(uint8_t(bytes[i + 1])) << 8;
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += k[v >> 6 & 63];
        out += '=';
    }
    return out;
}

} // namespace app
