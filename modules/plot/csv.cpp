// plot: CSV export of plotted series (wide when all share one x grid, long otherwise).
#include "plot/plot.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>

namespace plot {

namespace {

size_t sampleCount(const Series& s) {
    return std::min(s.x.size(), s.y.size());
}
bool hasBand(const Series& s) {
    const size_t n = sampleCount(s);
    return n > 0 && s.bandLo.size() >= n && s.bandHi.size() >= n;
}

// RFC 4180 quoting when needed.
std::string field(const std::string& s) {
    if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c;
    }
    return q + '"';
}

std::string seriesName(const Series& s, size_t index) {
    return s.label.empty() ? "series " + std::to_string(index + 1) : s.label;
}

bool sameGrid(const std::vector<Series>& series) {
    if (series.empty()) return true;
    const size_t n = sampleCount(series[0]);
    for (const Series& s : series) {
        if (sampleCount(s) != n) return false;
        if (!std::equal(s.x.begin(), s.x.begin() + static_cast<std::ptrdiff_t>(n),
                        series[0].x.begin()))
            return false;
    }
    return true;
}

} // namespace

std::string toCsv(const std::vector<Series>& series, const std::string& xName) {
    std::string out;
    if (sameGrid(series)) {
        out += field(xName);
        for (size_t k = 0; k < series.size(); ++k) {
            const std::string name = seriesName(series[k], k);
            out += ',' + field(name);
            if (hasBand(series[k])) out += ',' + field(name + " lo") + ',' + field(name + " hi");
        }
        out += '\n';
        const size_t n = series.empty() ? 0 : sampleCount(series[0]);
        for (size_t i = 0; i < n; ++i) {
            core::appendShortest(out, series[0].x[i]);
            for (const Series& s : series) {
                out += ',';
                core::appendShortest(out, s.y[i]);
                if (!hasBand(s)) continue;
                out += ',';
                core::appendShortest(out, s.bandLo[i]);
                out += ',';
                core::appendShortest(out, s.bandHi[i]);
            }
            out += '\n';
        }
        return out;
    }

    const bool anyBand = std::any_of(series.begin(), series.end(), hasBand);
    out += "label," + field(xName) + ",y" + (anyBand ? ",lo,hi" : "") + '\n';
    for (size_t k = 0; k < series.size(); ++k) {
        const Series& s = series[k];
        const std::string name = field(seriesName(s, k));
        const bool band = hasBand(s);
        for (size_t i = 0; i < sampleCount(s); ++i) {
            out += name + ',';
            core::appendShortest(out, s.x[i]);
            out += ',';
            core::appendShortest(out, s.y[i]);
            if (anyBand) {
                out += ',';
                if (band) core::appendShortest(out, s.bandLo[i]);
                out += ',';
                if (band) core::appendShortest(out, s.bandHi[i]);
            }
            out += '\n';
        }
    }
    return out;
}

void writeCsv(const std::filesystem::path& path, const std::vector<Series>& series,
              const std::string& xName) {
    core::writeFile(path, toCsv(series, xName));
}

} // namespace plot
