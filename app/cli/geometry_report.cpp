// The geometry suite's reports (compare_geometry.h): report.md and report.html with a model ×
// shape summary (the median rel_l2 over the presets and channels, and how often the model ranks
// first), then per shape a model × (preset, channel) table and the pictures of each case
// (reference | models above, signed error maps below, geometry_images.h).
#include "cli/compare_command.h"
#include "cli/compare_geometry.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/statistics.h"
#include "mesh/suite.h"
#include "pipeline/geometry_images.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {

std::string geometryPercent(double v, int digits = 3) {
    return formatScore(100 * v, digits) + " %";
}

std::string cellText(const GeometryRow& r) {
    if (!r.score.problem.empty()) return "no image";
    return geometryPercent(r.score.relL2) + " ± " + formatScore(100 * r.score.relL2Se, 2) + " (" +
           (r.tie ? "=" : "") + std::to_string(r.rank) + ")";
}

// The summary's cell of a model and a shape: the median rel_l2 over its presets and channels
// (NaN when none has a score) and how often it ranks first.
struct SummaryCell {
    double median = std::nan("");
    int firsts = 0;
};
std::map<std::pair<std::string, std::string>, SummaryCell> summaryCells(const GeometryReport& r) {
    std::map<std::pair<std::string, std::string>, std::vector<double>> byModelShape;
    std::map<std::pair<std::string, std::string>, SummaryCell> cells;
    for (const GeometryRow& row : r.rows) {
        if (!row.score.problem.empty()) continue;
        byModelShape[{row.model, row.shape}].push_back(row.score.relL2);
        cells[{row.model, row.shape}].firsts += row.rank == 1;
    }
    for (auto& [key, v] : byModelShape)
        cells[key].median = core::median(v);
    return cells;
}

std::string summaryText(const SummaryCell& c) {
    return std::isfinite(c.median)
               ? geometryPercent(c.median) + " (" + std::to_string(c.firsts) + ")"
               : "—";
}

} // namespace

std::string geometrySummaryText(const GeometryReport& r) {
    const auto cells = summaryCells(r);
    size_t w = 5;
    for (const std::string& m : r.models)
        w = std::max(w, m.size());
    std::vector<size_t> widths;
    for (const std::string& shape : r.shapes) {
        size_t cw = shape.size();
        for (const std::string& model : r.models)
            if (const auto it = cells.find({model, shape}); it != cells.end())
                cw = std::max(cw, summaryText(it->second).size());
        widths.push_back(cw);
    }
    // "—" is one column wide and three bytes long: pad by what a terminal shows
    const auto pad = [](const std::string& t, size_t width) {
        const size_t shown = t == "—" ? 1 : t.size();
        return t + std::string(width > shown ? width - shown : 0, ' ');
    };
    std::string out =
        "median rel_l2 over presets and channels (times ranked first)\n" + pad("model", w);
    for (size_t k = 0; k < r.shapes.size(); ++k)
        out += "  " + pad(r.shapes[k], widths[k]);
    out += "\n";
    for (const std::string& model : r.models) {
        out += pad(model, w);
        for (size_t k = 0; k < r.shapes.size(); ++k) {
            const auto it = cells.find({model, r.shapes[k]});
            out += "  " + pad(it == cells.end() ? "—" : summaryText(it->second), widths[k]);
        }
        out.erase(out.find_last_not_of(' ') + 1); // no padding after the last column
        out += "\n";
    }
    return out;
}

void writeGeometryReports(const fs::path& dir, const GeometryReport& r) {
    const auto cells = summaryCells(r);
    std::map<std::tuple<std::string, std::string, std::string, std::string>, const GeometryRow*>
        cell;                                                 // (shape, model, preset, channel)
    std::vector<std::pair<std::string, std::string>> columns; // (preset, channel) in row order
    for (const GeometryRow& row : r.rows) {
        cell[{row.shape, row.model, row.preset, row.channel}] = &row;
        if (std::find(columns.begin(), columns.end(), std::pair{row.preset, row.channel}) ==
            columns.end())
            columns.emplace_back(row.preset, row.channel);
    }
    const GeometrySettings& s = r.settings;
    std::ostringstream md, html;
    const std::string intro =
        "Each model's BSSRDF-integrated image of a shape against the volumetric path tracer's "
        "image of the same shape, light and orthographic camera (" +
        std::to_string(s.size) + "² pixels; reference " + std::to_string(s.referenceSpp) +
        " paths per covered pixel in each of 3 independent estimates; " +
        std::to_string(s.modelSpp) + " BSSRDF samples per pixel, " + core::nameOf(s.sampling) +
        " sampling; seed " + std::to_string(s.seed) +
        "). Shape lengths are in units of each channel's l_d. rel_l2 is the relative L2 error "
        "over the pixels that show the object, with both images' noise removed "
        "(app/pipeline/geometry_scoring.h); ± is its standard error; (n) the rank within the "
        "shape, preset and channel, = a tie within the noise.";
    md << "# Geometry suite\n\n"
       << intro << "\n\n## Summary: median rel_l2 over presets and "
       << "channels (times ranked first)\n\n| model |";
    html << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>Geometry suite</title>"
            "<style>body{font-family:sans-serif;background:#111;color:#ddd}"
            "table{border-collapse:collapse}td,th{border:1px solid #444;padding:3px 8px;"
            "text-align:right}th{background:#222}td.l{text-align:left}"
            "figure{display:inline-block;margin:6px}figcaption{font-size:80%}"
            "img{image-rendering:pixelated}</style></head><body><h1>Geometry suite</h1><p>"
         << htmlEscape(intro)
         << "</p><h2>Summary: median rel_l2 over presets and channels (times ranked first)</h2>"
            "<table><tr><th>model</th>";
    for (const std::string& shape : r.shapes) {
        md << " " << shape << " |";
        html << "<th>" << htmlEscape(shape) << "</th>";
    }
    md << "\n|---|";
    html << "</tr>\n";
    for (size_t k = 0; k < r.shapes.size(); ++k)
        md << "---|";
    md << "\n";
    for (const std::string& model : r.models) {
        md << "| " << model << " |";
        html << "<tr><td class=l>" << htmlEscape(model) << "</td>";
        for (const std::string& shape : r.shapes) {
            const auto it = cells.find({model, shape});
            const double m = it == cells.end() ? std::nan("") : it->second.median;
            const std::string text = it == cells.end() ? "—" : summaryText(it->second);
            md << " " << text << " |";
            html << "<td"
                 << (std::isfinite(m)
                         ? " style=\"background:" + scoreCellColour(m) + ";color:#000\""
                         : std::string())
                 << ">" << htmlEscape(text) << "</td>";
        }
        md << "\n";
        html << "</tr>\n";
    }
    html << "</table>\n";
    for (const std::string& shape : r.shapes) {
        const mesh::SuiteShape sh = mesh::makeSuiteShape(shape, "report");
        md << "\n## " << shape << "\n\n";
        std::string description;
        for (const mesh::SuiteKind& k : mesh::suiteKinds())
            if (sh.kind == k.name) description = k.description;
        md << description << "; longest axis " << formatScore(sh.longestAxis, 3)
           << " l_d; light towards (" << formatScore(sh.light[0], 3) << ", "
           << formatScore(sh.light[1], 3) << ", " << formatScore(sh.light[2], 3)
           << ").\n\n| model |";
        html << "<h2>" << htmlEscape(shape) << "</h2><p>" << htmlEscape(description)
             << "</p><table><tr><th>model</th>";
        for (const auto& [preset, ch] : columns) {
            md << " " << preset << " " << ch << " |";
            html << "<th>" << htmlEscape(preset) << " " << ch << "</th>";
        }
        md << "\n|---|";
        for (size_t k = 0; k < columns.size(); ++k)
            md << "---|";
        md << "\n";
        html << "</tr>\n";
        for (const std::string& model : r.models) {
            md << "| " << model << " |";
            html << "<tr><td class=l>" << htmlEscape(model) << "</td>";
            for (const auto& [preset, ch] : columns) {
                const auto it = cell.find({shape, model, preset, ch});
                const GeometryRow* row = it == cell.end() ? nullptr : it->second;
                const std::string text = row ? cellText(*row) : "—";
                md << " " << text << " |";
                const bool coloured = row && row->score.problem.empty();
                html << "<td"
                     << (coloured ? " style=\"background:" + scoreCellColour(row->score.relL2) +
                                        ";color:#000\""
                                  : std::string())
                     << (row && !row->score.problem.empty()
                             ? " title=\"" + htmlEscape(row->score.problem) + "\""
                             : std::string())
                     << ">" << htmlEscape(text) << "</td>";
            }
            md << "\n";
            html << "</tr>\n";
        }
        html << "</table>\n";
        md << "\n";
        for (const auto& [preset, ch] : columns) {
            const std::string file = geometryPictureName(shape, preset, ch);
            std::error_code ec;
            if (!fs::exists(dir / "images" / file, ec)) continue;
            std::string caption = preset + " " + ch + ": reference";
            for (const std::string& m : r.models)
                caption += " | " + m;
            caption += " (signed error below, ±" + formatScore(100 * kGeometryErrorRange, 2) +
                       " % saturates)";
            md << "![" << caption << "](images/" << file << ")\n\n";
            html << "<figure><img alt=\"" << htmlEscape(caption) << "\" src=\"images/"
                 << htmlEscape(file) << "\"><figcaption>" << htmlEscape(caption)
                 << "</figcaption></figure>\n";
        }
    }
    html << "</body></html>\n";
    core::writeFile(dir / "report.md", md.str());
    core::writeFile(dir / "report.html", html.str());
}

} // namespace app
