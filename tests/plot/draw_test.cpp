// plot: drawPlot builds sane ImGui draw lists headless (no GL: an ImGui context with a built
// font atlas is enough to run frames and inspect the vertices).
#include "plot/plot_draw.h"

#include "../support/imgui_context.h"
#include "plot_helpers.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

namespace {

class PlotDraw : public testing::Test {
  protected:
    testsupport::ImGuiContextForTest imgui{ImVec2(1024, 768), 1.0f / 60.0f};

    // One frame with the plot in a fixed window; returns the widget's state.
    plot::PlotState frame(ImVec2 mouse, const std::vector<plot::Series>& s, const plot::Axis& x,
                          const plot::Axis& y, ImVec2 size = ImVec2(700, 450)) {
        ImGui::GetIO().MousePos = mouse;
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(10, 10));
        ImGui::SetNextWindowSize(ImVec2(800, 600));
        ImGui::Begin("plot window", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
        const plot::PlotState st = plot::drawPlot("##profile", size, s, x, y, "Pencil beam R(r)",
                                                  "normalised: integral 2 pi r R(r) dr = albedo");
        ImGui::End();
        ImGui::Render();
        return st;
    }

    static std::vector<plot::Series> profiles() {
        std::vector<plot::Series> out;
        for (int k = 0; k < 3; ++k) {
            plot::Series s;
            s.label = "model " + std::to_string(k);
            s.color = plot::defaultColor(k);
            s.dashed = k == 1;
            for (int i = 0; i < 600; ++i) {
                const double r = i * 0.02;
                s.x.push_back(r);
                s.y.push_back(std::exp(-(k + 1) * r) / (r + 0.05));
            }
            s.y[100] = NAN;
            s.y[200] = 0.0; // breaks the line on a log axis
            s.y[300] = INFINITY;
            if (k == 2) { // a reference with a ±2σ band whose bottom goes <= 0
                s.marker = true;
                for (double v : s.y) {
                    s.bandLo.push_back(v * 0.8 - 1e-4);
                    s.bandHi.push_back(v * 1.2);
                }
            }
            out.push_back(std::move(s));
        }
        return out;
    }
};

using plot_test::axis;

// Every vertex of the plot window is finite and near the widget rect.
void expectSaneVertices(const plot::PlotState& st) {
    const ImDrawData* dd = ImGui::GetDrawData();
    ASSERT_NE(dd, nullptr);
    const ImDrawList* dl = dd->CmdLists[0];
    ASSERT_GT(dl->VtxBuffer.Size, 0);
    for (const ImDrawVert& v : dl->VtxBuffer) {
        ASSERT_TRUE(std::isfinite(v.pos.x) && std::isfinite(v.pos.y));
        EXPECT_GE(v.pos.x, std::min(st.min.x, 10.0f) - 24.0f);
        EXPECT_LE(v.pos.x, std::max(st.max.x, 810.0f) + 24.0f);
        EXPECT_GE(v.pos.y, std::min(st.min.y, 10.0f) - 24.0f);
        EXPECT_LE(v.pos.y, std::max(st.max.y, 610.0f) + 24.0f);
    }
}

TEST_F(PlotDraw, DrawsAllScalesWithoutGarbage) {
    const std::vector<plot::Series> s = profiles();
    for (plot::Scale sc : {plot::Scale::Linear, plot::Scale::Log, plot::Scale::Sqrt}) {
        SCOPED_TRACE(plot::scaleName(sc));
        const plot::Axis x = plot::autoRange(s, plot::Scale::Linear, false);
        plot::Axis y = plot::autoRange(s, sc, true, 8);
        y.label = "R(r) [1/mm^2]";
        const plot::PlotState st = frame(ImVec2(-FLT_MAX, -FLT_MAX), s, x, y);
        EXPECT_FALSE(st.hovered);
        EXPECT_FLOAT_EQ(st.max.x - st.min.x, 700.0f);
        EXPECT_FLOAT_EQ(st.max.y - st.min.y, 450.0f);
        EXPECT_GT(st.plotMin.x, st.min.x);
        EXPECT_LT(st.plotMax.y, st.max.y);
        EXPECT_GT(st.plotMax.x - st.plotMin.x, 500.0f);
        EXPECT_GT(st.plotMax.y - st.plotMin.y, 300.0f);
        EXPECT_GT(ImGui::GetDrawData()->TotalVtxCount, 3000);
        expectSaneVertices(st);
    }
}

TEST_F(PlotDraw, HoverGivesRowsAndTooltip) {
    const std::vector<plot::Series> s = profiles();
    const plot::Axis x = axis(0, 12, plot::Scale::Linear, "r [mm]");
    const plot::Axis y = axis(1e-6, 30, plot::Scale::Log);
    const plot::PlotState first = frame(ImVec2(-FLT_MAX, -FLT_MAX), s, x, y);
    // r ~ 4.9: away from the NaN / zero / inf samples at r = 2, 4, 6.
    const ImVec2 mouse(first.plotMin.x + 0.41f * (first.plotMax.x - first.plotMin.x),
                       0.5f * (first.plotMin.y + first.plotMax.y));
    frame(mouse, s, x, y); // hovered window is decided from the previous frame
    const plot::PlotState st = frame(mouse, s, x, y);
    ASSERT_TRUE(st.hovered);
    EXPECT_NEAR(st.hoverX, 0.41 * 12.0, 12.0 / (st.plotMax.x - st.plotMin.x));
    ASSERT_EQ(st.rows.size(), 3u);
    for (size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(st.rows[k].label, s[k].label);
        ASSERT_TRUE(std::isfinite(st.rows[k].y));
        EXPECT_NEAR(st.rows[k].y, std::exp(-(k + 1.0) * st.hoverX) / (st.hoverX + 0.05),
                    1e-3 * st.rows[k].y);
    }
    EXPECT_TRUE(std::isfinite(st.rows[2].lo));
    EXPECT_GE(ImGui::GetDrawData()->CmdListsCount, 2); // the plot window + the tooltip
    expectSaneVertices(st);
}

// A text too wide for its place is cut at a whole character and says so with "..." (the
// titles of a narrow plot were cut mid-glyph at its edge, "R_d per unit pow").
TEST_F(PlotDraw, ElidedTextFitsAndSaysItWasCut) {
    ImGui::NewFrame();
    const std::string text = "normalised: integral 2 pi r R(r) dr = albedo";
    EXPECT_EQ(plot::elided(text, 1000), text);
    const std::string cut = plot::elided(text, 120);
    EXPECT_LE(ImGui::CalcTextSize(cut.c_str()).x, 120.0f);
    ASSERT_GT(cut.size(), 3u);
    EXPECT_EQ(cut.substr(cut.size() - 3), "...");
    EXPECT_EQ(text.rfind(cut.substr(0, cut.size() - 3), 0), 0u) << cut;
    // a multi-byte character is kept or dropped whole, never split
    const std::string greek = "\u03c3\u03c3\u03c3\u03c3\u03c3\u03c3\u03c3\u03c3\u03c3\u03c3";
    for (float w = 10; w < 120; w += 3) {
        const std::string g = plot::elided(greek, w);
        const bool wasCut = g.size() >= 3 && g.compare(g.size() - 3, 3, "...") == 0;
        const std::string kept = wasCut ? g.substr(0, g.size() - 3) : g;
        EXPECT_EQ(kept.size() % 2, 0u) << w;
    }
    ImGui::EndFrame();
}

TEST_F(PlotDraw, DegenerateInputsDoNotCrash) {
    std::vector<plot::Series> s(2);
    s[1].x = {1.0};
    s[1].y = {NAN};
    s[1].label = "one NaN sample";
    const plot::Axis bad = axis(0, 0, plot::Scale::Log);
    frame(ImVec2(-FLT_MAX, -FLT_MAX), {}, bad, bad);
    const plot::PlotState st = frame(ImVec2(300, 200), s, bad, bad, ImVec2(0, 0));
    EXPECT_GT(st.max.x - st.min.x, 100.0f); // size 0: the available region
    EXPECT_GT(st.max.y - st.min.y, 100.0f);
    expectSaneVertices(st);
}

} // namespace
