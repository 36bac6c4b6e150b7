// The scoreboard's reports (compare_command.h): report.md and one self-contained report.html (a
// table with cells coloured by rel_err, and per preset and channel the pencil plot of every model
// with the reference's ±2σ band, the ratio model/reference against r, and at θi > 0 polar heatmaps
// of the relative difference over the plane), the pictures drawn headless by the panels' own code
// (report_png.h) and also written to DIR/plots/ for report.md.
#include "cli/compare_command.h"

#include "core/core.h"
#include "core/text.h"
#include "gui/polar_heatmap.h"
#include "gui/report_png.h"
#include "pipeline/image_display.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

// rel_err → a cell colour from green (0) through yellow (10 %) to red (>= 30 %).
std::string scoreCellColour(double rel) {
    const double t = std::clamp(rel / 0.3, 0.0, 1.0);
    const int red = int(std::lround(255 * std::min(1.0, 2 * t)));
    const int green = int(std::lround(200 * std::min(1.0, 2 * (1 - t))));
    char b[16];
    std::snprintf(b, sizeof b, "#%02x%02x60", red, green);
    return b;
}

std::string htmlEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else if (c == '"')
            out += "&quot;";
        else
            out += c;
    }
    return out;
}

namespace {

// A file name from preset, channel and angle: letters, digits, '-' and '_' only.
std::string slug(const std::string& s) {
    std::string out;
    for (char c : s)
        out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
    return out;
}

constexpr int kPlotW = 560, kPlotH = 360, kDisc = 150;

struct Picture {
    std::string file, caption, png;
};

// The pencil plot and the ratio plot of one preset and channel.
std::vector<Picture> profilePictures(const ProfileCurves& p) {
    std::vector<plot::Series> series;
    plot::Series ref;
    ref.label = "path traced +-2 se";
    ref.x = p.r;
    ref.y = p.ref;
    for (size_t i = 0; i < p.r.size(); ++i) {
        ref.bandLo.push_back(p.ref[i] - 2 * p.refSe[i]);
        ref.bandHi.push_back(p.ref[i] + 2 * p.refSe[i]);
    }
    ref.color = 0xffffffff;
    ref.marker = true;
    ref.compareTo = 0;
    series.push_back(ref);
    for (size_t k = 0; k < p.models.size(); ++k) {
        plot::Series s;
        s.label = p.models[k].first;
        s.x = p.r;
        s.y = p.models[k].second;
        s.color = plot::defaultColor(k);
        s.dashed = k % 2 == 1;
        s.compareTo = 0;
        series.push_back(s);
    }
    const std::string ch(1, "RGB"[p.channel]);
    const std::string base = slug(p.preset) + "_" + ch;
    const std::string sub =
        "l_d = " + formatScore(p.ld, 3) + " mm, R_d/(1 - R_sp) per unit power entering";
    plot::Axis x{0, 4.5 * p.ld, plot::Scale::Linear, "r [mm]"};
    plot::Axis y = plot::autoRange(series, plot::Scale::Log, true, 6);
    y.label = "R(r) [1/mm^2]";
    std::vector<Picture> out;
    out.push_back(
        {base + "_profile.png", p.preset + " " + ch + ": radial profiles",
         plotPng(kPlotW, kPlotH, series, x, y, p.preset + " " + ch + ", theta_i = 0", sub)});
    const std::vector<plot::Series> ratio = plot::relativeTo(series, plot::Relation::Ratio);
    plot::Axis yr = plot::autoRange(ratio, plot::Scale::Linear, true);
    yr.lo = std::max(yr.lo, 0.0);
    yr.hi = std::min(yr.hi, 3.0);
    yr.label = "R_model / R_ref";
    out.push_back(
        {base + "_ratio.png", p.preset + " " + ch + ": ratio to the reference",
         plotPng(kPlotW, kPlotH, ratio, x, yr, p.preset + " " + ch + ": model / path traced",
                 "band: the reference's own +-2 standard errors")});
    return out;
}

} // namespace

std::vector<std::pair<std::string, std::string>> writeProfilePictures(const fs::path& dir,
                                                                      const ProfileCurves& p) {
    std::vector<std::pair<std::string, std::string>> out;
    fs::create_directories(dir);
    for (const Picture& pic : profilePictures(p)) {
        core::writeFile(dir / pic.file, pic.png);
        out.emplace_back(pic.file, pic.caption);
    }
    return out;
}

namespace {

// Reference R and each model's signed relative difference over the plane, one disc each.
Picture slicePicture(const SliceMaps& s) {
    const std::string ch(1, "RGB"[s.channel]);
    const std::string angle = formatScore(s.thetaI, 3);
    const int n = int(s.models.size()) + 1;
    const int w = std::max(kPlotW, n * (kDisc + 12) + 12), h = kDisc + 64;
    double lo = INFINITY, hi = 0;
    for (double v : s.refR)
        if (v > 0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    auto logColour = [&](double v) -> ImU32 {
        if (!(v > 0) || !std::isfinite(v) || !(hi > lo)) return IM_COL32(0, 0, 0, 255);
        const float t = float((std::log(v) - std::log(lo)) / (std::log(hi) - std::log(lo)));
        const auto c = divergingColor(std::clamp(2 * t - 1, -1.0f, 1.0f));
        return IM_COL32(c[0], c[1], c[2], 255);
    };
    std::string png = renderImGuiPng(w, h, [&] {
        ImGui::Text("%s %s, theta_i = %s deg: path traced R (log colour), then (model - ref)/ref "
                    "per model (blue -50 %% ... red +50 %%, grey: within 2 se)",
                    s.preset.c_str(), ch.c_str(), angle.c_str());
        int none = -1;
        ImGui::BeginGroup();
        ImGui::TextUnformatted("path traced");
        polarHeatmap("##ref", float(kDisc), s.bins,
                     {s.refR, [&](size_t i) { return logColour(s.refR[i]); }}, none);
        ImGui::EndGroup();
        for (size_t k = 0; k < s.models.size(); ++k) {
            const std::vector<double>& m = s.models[k].second;
            ImGui::SameLine();
            ImGui::BeginGroup();
            ImGui::TextUnformatted(s.models[k].first.c_str());
            polarHeatmap(("##m" + std::to_string(k)).c_str(), float(kDisc), s.bins,
                         {m,
                          [&](size_t i) -> ImU32 {
                              if (!(s.refR[i] > 0) || !std::isfinite(m[i]))
                                  return IM_COL32(0, 0, 0, 255);
                              if (std::abs(m[i] - s.refR[i]) < 2 * s.refSe[i])
                                  return IM_COL32(90, 90, 90, 255);
                              const float t = float((m[i] - s.refR[i]) / s.refR[i] / 0.5);
                              const auto c = divergingColor(std::clamp(t, -1.0f, 1.0f));
                              return IM_COL32(c[0], c[1], c[2], 255);
                          }},
                         none);
            ImGui::EndGroup();
        }
    });
    return {slug(s.preset) + "_" + ch + "_theta" + slug(angle) + "_slice.png",
            s.preset + " " + ch + " at θi = " + angle + "°: relative difference over the plane",
            std::move(png)};
}

std::string angleList(const std::vector<double>& a) {
    std::string s;
    for (double v : a)
        s += (s.empty() ? "" : ", ") + formatScore(v, 3) + "°";
    return s;
}

// "Skin1 B, θi 0°" (or "theta_i 0" in plain text): where a row lies
std::string rowPlace(const ScoreRow& r, bool plain) {
    return r.preset + " " + r.channel + ", " + (plain ? "theta_i " : "θi ") +
           formatScore(r.thetaI, 3) + (plain ? "" : "°");
}

std::string percent(double v, int digits) {
    return formatScore(100 * v, digits) + " %";
}

} // namespace

std::string modelSummaryText(const std::vector<ScoreRow>& rows) {
    const std::vector<ModelSummary> models = summarizeModels(rows);
    size_t w = 5;
    for (const ModelSummary& m : models)
        w = std::max(w, m.model.size());
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-*s  %-9s  %-14s  %s\n", int(w), "model", "rank 1",
                  "median rel_err", "largest rel_err");
    out += line;
    for (const ModelSummary& m : models) {
        const std::string first = std::to_string(m.first) + " / " + std::to_string(m.rows);
        std::snprintf(line, sizeof line, "%-*s  %-9s  %-14s  %s (%s)\n", int(w), m.model.c_str(),
                      first.c_str(), percent(m.medianRelErr, 3).c_str(),
                      percent(m.worst.relErr, 3).c_str(), rowPlace(m.worst, true).c_str());
        out += line;
    }
    return out;
}

void writeReports(const fs::path& dir, const CompareReport& r, bool pictures) {
    std::vector<Picture> pics;
    if (pictures) {
        for (const ProfileCurves& p : r.profiles)
            for (Picture& q : profilePictures(p))
                pics.push_back(std::move(q));
        for (const SliceMaps& s : r.slices)
            pics.push_back(slicePicture(s));
        fs::create_directories(dir / "plots");
        for (const Picture& p : pics)
            core::writeFile(dir / "plots" / p.file, p.png);
    }
    std::ostringstream md, html;
    md << "# BSSRDF scoreboard\n\nθi: " << angleList(r.thetaI) << "; " << r.paths
       << " reference paths per preset, channel and angle. rel_err is the RMS relative error "
          "over ln r in [0.1, 4] l_d with the reference's own noise removed "
          "(modules/core/relative_error.h): at θi = 0 of the radial profile against the slab "
          "tracer; at θi > 0 over the plane (ln r, θs), and rel_err_dir also over the exit "
          "directions, against the connections estimate (pipeline/scoring.h, "
          "pipeline/scoring_oblique.h). ± is the standard error from the reference; `=` marks a "
          "tie with the best of its preset, channel and angle. The first table takes each model "
          "over "
          "every row: in how many it ranks 1 (ties included), its median rel_err and its "
          "largest.\n\n";
    // each model over every row first: how often it ranks 1, its median and largest rel_err
    const std::vector<ModelSummary> models = summarizeModels(r.rows);
    md << "| model | rank 1 | median rel_err | largest rel_err |\n|---|---|---|---|\n";
    for (const ModelSummary& m : models)
        md << "| " << m.model << " | " << m.first << " / " << m.rows << " | "
           << percent(m.medianRelErr, 3) << " | " << percent(m.worst.relErr, 3) << " ("
           << rowPlace(m.worst, false) << ") |\n";
    md << "\n| preset | ch | θi | model | rank | rel_err | rel_err_dir | ratio at 1 l_d | ratio at "
          "4 "
          "l_d | total ratio | error > 5 % from (l_d) |\n|---|---|---|---|---|---|---|---|---|---|"
          "---|\n";
    html << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>BSSRDF scoreboard</title>"
            "<style>body{font-family:sans-serif;background:#111;color:#ddd}"
            "table{border-collapse:collapse}td,th{border:1px solid #444;padding:3px 8px;"
            "text-align:right}th{background:#222}td.l{text-align:left}"
            "figure{display:inline-block;margin:6px}figcaption{font-size:80%}</style></head><body>"
         << "<h1>BSSRDF scoreboard</h1><p>&theta;<sub>i</sub>: " << htmlEscape(angleList(r.thetaI))
         << "; " << r.paths
         << " reference paths per preset, channel and angle. rel_err is the RMS relative error "
            "over ln r in [0.1, 4] l<sub>d</sub> with the reference's own noise removed: at "
            "&theta;<sub>i</sub> = 0 of the radial profile against the slab tracer; at "
            "&theta;<sub>i</sub> &gt; 0 over the plane (ln r, &theta;<sub>s</sub>), and "
            "rel_err_dir also over the exit directions, against the connections estimate. "
            "&plusmn; is the standard error from the reference; = marks a tie with the best. The "
            "first table takes each model over every row: in how many it ranks 1 (ties "
            "included), its median rel_err and its largest.</p>"
         << "<table><tr><th>model</th><th>rank 1</th><th>median rel_err</th><th>largest "
            "rel_err</th></tr>\n";
    for (const ModelSummary& m : models)
        html << "<tr><td class=l>" << htmlEscape(m.model) << "</td><td>" << m.first << " / "
             << m.rows << "</td><td style=\"background:" << scoreCellColour(m.medianRelErr)
             << ";color:#000\">" << percent(m.medianRelErr, 3) << "</td><td>"
             << percent(m.worst.relErr, 3) << " (" << htmlEscape(rowPlace(m.worst, false))
             << ")</td></tr>\n";
    html << "</table><p></p>\n"
         << "<table><tr><th>preset</th><th>ch</th><th>&theta;<sub>i</sub></th><th>model</th>"
            "<th>rank</th><th>rel_err</th><th>rel_err_dir</th><th>ratio 1 l<sub>d</sub></th>"
            "<th>ratio 4 l<sub>d</sub></th><th>total ratio</th><th>error &gt; 5 % from "
            "(l<sub>d</sub>)</th></tr>\n";
    for (const ScoreRow& s : r.rows) {
        const std::string rank = (s.tie ? "=" : "") + std::to_string(s.rank);
        const std::string rel =
            formatScore(100 * s.relErr, 3) + " % ± " + formatScore(100 * s.relErrSe, 2) + " %";
        const std::string dir2 = s.relErrDir
                                     ? formatScore(100 * *s.relErrDir, 3) + " % ± " +
                                           formatScore(100 * s.relErrDirSe.value_or(0), 2) + " %"
                                     : "—";
        const std::string err5 = s.rErr5Ld ? formatScore(*s.rErr5Ld, 3) : "none";
        const std::string th = formatScore(s.thetaI, 3);
        md << "| " << s.preset << " | " << s.channel << " | " << th << " | " << s.model << " | "
           << rank << " | " << rel << " | " << dir2 << " | " << formatScore(s.ratio1) << " | "
           << formatScore(s.ratio4) << " | " << formatScore(s.totalRatio) << " | " << err5
           << " |\n";
        html << "<tr><td class=l>" << htmlEscape(s.preset) << "</td><td>" << s.channel
             << "</td><td>" << th << "</td><td class=l>" << htmlEscape(s.model) << "</td><td>"
             << rank << "</td><td style=\"background:" << scoreCellColour(s.relErr)
             << ";color:#000\">" << htmlEscape(rel) << "</td><td"
             << (s.relErrDir
                     ? " style=\"background:" + scoreCellColour(*s.relErrDir) + ";color:#000\""
                     : std::string())
             << ">" << htmlEscape(dir2) << "</td><td>" << formatScore(s.ratio1) << "</td><td>"
             << formatScore(s.ratio4) << "</td><td>" << formatScore(s.totalRatio) << "</td><td>"
             << err5 << "</td></tr>\n";
    }
    html << "</table>\n";
    if (!pics.empty()) {
        md << "\n## Plots\n\n";
        html << "<h2>Plots</h2>\n";
        for (const Picture& p : pics) {
            md << "![" << p.caption << "](plots/" << p.file << ")\n";
            html << "<figure><img alt=\"" << htmlEscape(p.caption)
                 << "\" src=\"data:image/png;base64," << base64(p.png) << "\"><figcaption>"
                 << htmlEscape(p.caption) << "</figcaption></figure>\n";
        }
    }
    html << "</body></html>\n";
    core::writeFile(dir / "report.md", md.str());
    core::writeFile(dir / "report.html", html.str());
}

} // namespace app
