// bssrdf/table_model: reading radial profiles and path-traced tables into a model's generated
// shader section (see table_model.h).
#include "bssrdf/table_model.h"

#include "bssrdf/detail/text_lines.h"
#include "bssrdf/oblique_table.h"
#include "core/core.h"
#include "core/text.h"
#include "pathtrace/bssrdf_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace bssrdf {
namespace {
namespace fs = std::filesystem;

std::string trimmed(std::string_view s) {
    return std::string(detail::trim(s));
}

std::vector<std::string> splitOn(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
        out.push_back(trimmed(item));
    if (!s.empty() && s.back() == sep) out.emplace_back();
    return out;
}

bool parseNumber(const std::string& s, double& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size();
}

// Checks and appends one row of a radial table; `where` names the file (and line) in errors.
void addRow(RadialTable& t, double r, const std::array<double, 3>& v, const std::string& file,
            int line) {
    auto fail = [&](const std::string& msg) { throw core::Error(file, line, msg); };
    if (!std::isfinite(r) || r < 0)
        fail("r_mm must be a finite radius >= 0, got " + core::formatNumber(r));
    if (!t.r.empty() && !(r > t.r.back()))
        fail("r_mm must increase from row to row (" + core::formatNumber(r) + " after " +
             core::formatNumber(t.r.back()) + ")");
    static const char* kNames[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(v[size_t(c)]) || v[size_t(c)] < 0)
            fail(std::string(kNames[c]) + " must be finite and >= 0, got " +
                 core::formatNumber(v[size_t(c)]));
    if (t.r.size() >= kMaxTableRadii)
        fail("more than " + std::to_string(kMaxTableRadii) + " rows: resample the profile");
    t.r.push_back(r);
    t.rgb.push_back(v);
}

// The θi = 0 slice of a table as R_d(r) per unit power entering at the radial bin centres.
std::vector<double> normalIncidence(const pathtrace::BssrdfTable& t, const std::string& name) {
    const auto& th = t.settings.thetaIDeg;
    const auto it = std::find(th.begin(), th.end(), 0.0);
    if (it == th.end())
        throw core::Error(name, 0,
                          "has no theta_i 0 slice: a model needs normal incidence (estimate "
                          "--theta-i 0,...)");
    const pathtrace::BssrdfSlice s = t.slice(size_t(it - th.begin()));
    const auto& b = t.settings.bins;
    std::vector<double> out(size_t(b.rBins), 0.0);
    for (int ir = 0; ir < b.rBins; ++ir) {
        double sum = 0;
        for (int is = 0; is < b.thetaSBins; ++is) // θs bins of one ring have equal areas
            sum += s.R[size_t(ir * b.thetaSBins + is)];
        out[size_t(ir)] = sum / b.thetaSBins / (1.0 - s.specular);
    }
    return out;
}

// Reads the tables of an `estimate` directive and their media (one per channel).
std::vector<pathtrace::BssrdfTable> readTables(const std::vector<fs::path>& files,
                                               std::vector<Model::TableMedium>& media) {
    std::vector<pathtrace::BssrdfTable> tables;
    for (const auto& f : files) {
        tables.push_back(pathtrace::readTable(f));
        const auto& m = tables.back().medium;
        media.push_back({m.sigmaA, m.sigmaS, m.g, m.eta});
    }
    if (tables.size() == 1) media.assign(3, media[0]);
    return tables;
}

RadialTable radialEstimates(const std::vector<pathtrace::BssrdfTable>& tables,
                            const std::vector<std::string>& names) {
    const auto edges = tables[0].settings.bins.rEdges();
    for (size_t i = 1; i < tables.size(); ++i)
        if (tables[i].settings.bins.rEdges() != edges)
            throw core::Error(names[i], 0,
                              "its radial bins differ from " + names[0] +
                                  "'s: the channels of a table model share one radius grid");
    std::array<std::vector<double>, 3> channel;
    for (int c = 0; c < 3; ++c) {
        const size_t i = tables.size() == 1 ? 0 : size_t(c);
        channel[size_t(c)] = normalIncidence(tables[i], names[i]);
    }
    RadialTable t;
    for (size_t k = 0; k + 1 < edges.size(); ++k)
        addRow(t, 0.5 * (edges[k] + edges[k + 1]), {channel[0][k], channel[1][k], channel[2][k]},
               names[0], 0);
    return t;
}

// The attributes of an oblique table model follow from its data: not radial, dependent on Wi,
// and on Wo unless there is one direction cell. Claims the data contradict become notes.
void setObliqueAttributes(Model& m, const ObliqueTable& t) {
    std::string dropped;
    auto clear = [&](bool& attr, bool keep, const char* name) {
        if (attr && !keep) dropped += std::string(dropped.empty() ? "" : ", ") + name;
        attr = keep;
    };
    clear(m.attrs.radial, false, "radial");
    clear(m.attrs.noWi, false, "no_wi");
    clear(m.attrs.noWo, t.cells() == 1, "no_wo");
    if (!dropped.empty())
        m.notes.push_back(core::formatLocation(m.path, m.table->beginLine,
                                               "the table is oblique (non-radial): attribute(s) " +
                                                   dropped + " ignored"));
}

} // namespace

RadialTable readProfileCsv(const fs::path& file, const std::string& displayName) {
    std::string text;
    try {
        text = core::readFile(file);
    } catch (const core::Error& e) {
        throw core::Error(displayName, 0, e.message());
    }
    if (auto bad = core::firstInvalidUtf8(text))
        throw core::Error(displayName, core::lineOfOffset(text, *bad),
                          "not a UTF-8 text file (invalid byte at offset " + std::to_string(*bad) +
                              ")");
    RadialTable t;
    bool header = false;
    const auto lines = detail::splitLines(text);
    for (size_t i = 0; i < lines.size(); ++i) {
        const int lineNo = int(i) + 1;
        const std::string line = trimmed(lines[i]);
        if (line.empty() || line[0] == '#') continue;
        const auto cells = splitOn(line, ',');
        if (!header) {
            if (cells != std::vector<std::string>{"r_mm", "R", "G", "B"})
                throw core::Error(displayName, lineNo,
                                  "expected the header 'r_mm,R,G,B', got '" + line + "'");
            header = true;
            continue;
        }
        if (cells.size() != 4)
            throw core::Error(displayName, lineNo,
                              "expected 4 numbers r_mm,R,G,B, got " + std::to_string(cells.size()) +
                                  " fields");
        double v[4];
        for (int k = 0; k < 4; ++k)
            if (!parseNumber(cells[size_t(k)], v[k]))
                throw core::Error(displayName, lineNo,
                                  "'" + cells[size_t(k)] + "' is not a number");
        addRow(t, v[0], {v[1], v[2], v[3]}, displayName, lineNo);
    }
    if (!header) throw core::Error(displayName, 0, "empty: expected the header 'r_mm,R,G,B'");
    if (t.r.size() < 2)
        throw core::Error(displayName, 0,
                          "needs at least 2 rows to interpolate, got " +
                              std::to_string(t.r.size()));
    return t;
}

std::string radialTableGlsl(const RadialTable& t) {
    const size_t n = t.r.size();
    std::ostringstream g;
    g << "// generated from the table section: " << n << " radii, linear in r, 0 beyond\n";
    g << "const int TableN = " << n << ";\n";
    g << "const float TableR[" << n << "] = float[](";
    for (size_t i = 0; i < n; ++i)
        g << (i ? ", " : "") << detail::glslFloat(t.r[i]);
    g << ");\nconst vec3 TableV[" << n << "] = vec3[](";
    for (size_t i = 0; i < n; ++i)
        g << (i ? ", " : "") << "vec3(" << detail::glslFloat(t.rgb[i][0]) << ", "
          << detail::glslFloat(t.rgb[i][1]) << ", " << detail::glslFloat(t.rgb[i][2]) << ")";
    g << ");\n"
         "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
         "    float r = length(Xo - Xi);\n"
         "    if (r <= TableR[0]) return TableV[0];\n"
         "    if (r >= TableR[TableN - 1]) return vec3(0.0);\n"
         "    int lo = 0, hi = TableN - 1;\n"
         "    while (hi - lo > 1) {\n"
         "        int mid = (lo + hi) / 2;\n"
         "        if (TableR[mid] <= r) lo = mid; else hi = mid;\n"
         "    }\n"
         "    float t = (r - TableR[lo]) / (TableR[hi] - TableR[lo]);\n"
         "    return mix(TableV[lo], TableV[hi], t);\n"
         "}\n";
    return g.str();
}

void expandTable(Model& m, const fs::path& modelDir) {
    if (!m.table) return;
    const Section& s = *m.table;
    const auto lines = detail::splitLines(s.code);
    std::vector<std::string> directive;
    int directiveLine = 0;
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string line = trimmed(lines[i]);
        if (line.empty() || line[0] == '#') continue;
        if (!directive.empty())
            throw core::Error(m.path, s.firstLine + int(i),
                              "a table section holds one directive ('profile FILE' or 'estimate "
                              "FILE...')");
        std::istringstream words(line);
        for (std::string w; words >> w;)
            directive.push_back(w);
        directiveLine = s.firstLine + int(i);
    }
    if (directive.empty())
        throw core::Error(m.path, s.beginLine,
                          "empty table section: write 'profile FILE.csv' or 'estimate "
                          "FILE.bwtable [G.bwtable B.bwtable]'");
    const std::string kind = directive[0];
    std::vector<fs::path> files;
    std::vector<std::string> names;
    for (size_t i = 1; i < directive.size(); ++i) {
        const fs::path p(directive[i]);
        if (p.is_absolute())
            throw core::Error(m.path, directiveLine,
                              "'" + directive[i] + "': give the path relative to the model file");
        files.push_back(modelDir / p);
        names.push_back((fs::path(m.path).parent_path() / p).generic_string());
    }
    RadialTable t;
    if (kind == "profile") {
        if (files.size() != 1)
            throw core::Error(m.path, directiveLine, "'profile' takes one CSV file");
        t = readProfileCsv(files[0], names[0]);
    } else if (kind == "estimate") {
        if (files.size() != 1 && files.size() != 3)
            throw core::Error(m.path, directiveLine,
                              "'estimate' takes one table (all channels) or three (R G B)");
        const auto tables = readTables(files, m.tableMedia);
        if (!std::all_of(tables.begin(), tables.end(), isRadialTable)) {
            const ObliqueTable o = obliqueTable(tables, names);
            setObliqueAttributes(m, o);
            m.dataFiles = files;
            m.shader = Section{"shader", obliqueTableGlsl(o), s.firstLine, s.beginLine};
            return;
        }
        t = radialEstimates(tables, names);
    } else {
        throw core::Error(m.path, directiveLine,
                          "unknown table directive '" + kind + "' (expected profile or estimate)");
    }
    m.dataFiles = files;
    m.shader = Section{"shader", radialTableGlsl(t), s.firstLine, s.beginLine};
}

} // namespace bssrdf
