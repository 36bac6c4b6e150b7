// MCML .mco files: the reader, the byte-exact writer (MCML 1.2.2 mcmlio.c formats) and the
// conversions to and from the slab reference (mco.h).
#include "pathtrace/mco.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace pathtrace {

namespace {

// The lines of the file, each with its 1-based number, CR stripped.
struct Lines {
    std::vector<std::string> text;
    std::string file;
    size_t at = 0; // next line to read
};

bool isComment(const std::string& l) {
    const size_t first = l.find_first_not_of(" \t");
    return first == std::string::npos || l[first] == '#';
}

[[noreturn]] void fail(const Lines& ls, size_t index, const std::string& msg) {
    throw core::Error(ls.file, int(index + 1), msg);
}

// The next data line (not blank, not a comment); its index in `index`.
const std::string& nextData(Lines& ls, size_t& index, const std::string& what) {
    while (ls.at < ls.text.size() && isComment(ls.text[ls.at]))
        ++ls.at;
    if (ls.at >= ls.text.size())
        throw core::Error(ls.file, int(ls.text.size()), "the file ends before " + what);
    index = ls.at++;
    return ls.text[index];
}

// The leading numbers of a line (up to '#').
std::vector<double> numbers(const Lines& ls, size_t index, const std::string& line, size_t want,
                            const std::string& what) {
    std::istringstream in(line.substr(0, line.find('#')));
    std::vector<double> out;
    std::string token;
    while (out.size() < want && in >> token) {
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        if (*end != '\0' || !std::isfinite(v))
            fail(ls, index, what + ": '" + core::printableText(token) + "' is not a number");
        out.push_back(v);
    }
    if (out.size() < want)
        fail(ls, index,
             what + ": expected " + std::to_string(want) + " numbers, found " +
                 std::to_string(out.size()));
    return out;
}

// The leading numbers of the next data line (its index in `index`): the line is read first, so
// that messages name it whatever order a compiler evaluates arguments in.
std::vector<double> nextNumbers(Lines& ls, size_t& index, const std::string& what, size_t want,
                                const std::string& label) {
    const std::string& line = nextData(ls, index, what);
    return numbers(ls, index, line, want, label);
}

// Moves past the data line that starts with `key` (followed by a blank or the line's end).
void seekKey(Lines& ls, const std::string& key) {
    for (size_t i = ls.at; i < ls.text.size(); ++i) {
        const std::string& l = ls.text[i];
        if (isComment(l)) continue;
        const size_t first = l.find_first_not_of(" \t");
        if (l.compare(first, key.size(), key) == 0 &&
            (first + key.size() == l.size() || l[first + key.size()] == ' ' ||
             l[first + key.size()] == '\t')) {
            ls.at = i + 1;
            return;
        }
    }
    throw core::Error(ls.file, 0, "no section '" + key + "' after line " + std::to_string(ls.at));
}

// `count` numbers, one per data line.
std::vector<double> column(Lines& ls, const std::string& key, size_t count) {
    seekKey(ls, key);
    std::vector<double> out;
    for (size_t k = 0; k < count; ++k) {
        size_t index = 0;
        const std::string& l = nextData(ls, index, key + " value " + std::to_string(k + 1));
        out.push_back(
            numbers(ls, index, l, 1,
                    key + " value " + std::to_string(k + 1) + " of " + std::to_string(count))[0]);
    }
    return out;
}

// `count` numbers, free format over as many data lines as they take.
std::vector<double> block(Lines& ls, const std::string& key, size_t count) {
    seekKey(ls, key);
    std::vector<double> out;
    while (out.size() < count) {
        size_t index = 0;
        const std::string& l =
            nextData(ls, index, key + " value " + std::to_string(out.size() + 1));
        std::istringstream in(l);
        std::string token;
        while (in >> token) {
            char* end = nullptr;
            const double v = std::strtod(token.c_str(), &end);
            if (*end != '\0' || !std::isfinite(v))
                fail(ls, index,
                     key + ": '" + core::printableText(token) + "' is not a number (" +
                         std::to_string(out.size()) + " of " + std::to_string(count) +
                         " values read)");
            out.push_back(v);
        }
    }
    if (out.size() != count)
        throw core::Error(ls.file, int(ls.at),
                          key + ": " + std::to_string(out.size()) + " values, expected " +
                              std::to_string(count));
    return out;
}

std::string formatted(const char* fmt, ...) {
    char buf[256];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    return buf;
}

} // namespace

McoFile parseMco(const std::string& text, const std::string& displayName) {
    Lines ls;
    ls.file = displayName;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        ls.text.push_back(line);
    }
    McoFile m;
    size_t index = 0;
    {
        const std::string& l = nextData(ls, index, "the version line");
        std::istringstream v(l);
        v >> m.version;
        if (m.version != "A1" && m.version != "B1")
            fail(ls, index,
                 "not an MCML output file: the first line is '" + core::printableText(l) +
                     "', expected 'A1'");
    }
    for (const std::string& l : ls.text)
        if (l.rfind("# User time:", 0) == 0 || l.rfind("#  Simulation time", 0) == 0) {
            m.timeLine = l;
            break;
        }
    seekKey(ls, "InParm");
    {
        const std::string& l = nextData(ls, index, "the output file name");
        std::istringstream v(l);
        v >> m.outName;
    }
    {
        const double photons = nextNumbers(ls, index, "photons", 1, "photons")[0];
        if (!(photons >= 0 && photons <= 1e18))
            fail(ls, index, "the number of photons must be 0 … 1e18");
        m.photons = (long long)photons;
    }
    {
        const auto v = nextNumbers(ls, index, "dz, dr", 2, "dz, dr");
        m.dz = v[0];
        m.dr = v[1];
        const auto n = nextNumbers(ls, index, "nz, nr, na", 3, "nz, nr, na");
        for (double v : n)
            if (!(v >= 1 && v <= 100000)) fail(ls, index, "nz, nr, na must be 1 … 100000");
        if (!(m.dz > 0 && m.dr > 0)) fail(ls, index, "dz and dr must be > 0");
        m.nz = int(n[0]);
        m.nr = int(n[1]);
        m.na = int(n[2]);
        if (size_t(m.nr) * size_t(std::max(m.nz, m.na)) > 20000000)
            fail(ls, index, "nr × nz and nr × na must be at most 2e7 values");
    }
    const double layers = nextNumbers(ls, index, "the number of layers", 1, "layers")[0];
    if (!(layers >= 1 && layers <= 100)) fail(ls, index, "the number of layers must be 1 … 100");
    m.nAbove = nextNumbers(ls, index, "n above", 1, "n above")[0];
    for (int k = 0; k < int(layers); ++k) {
        const auto v = nextNumbers(ls, index, "a layer", 5,
                                   "layer " + std::to_string(k + 1) + " (n mua mus g d)");
        m.layers.push_back({v[0], v[1], v[2], v[3], v[4]});
    }
    m.nBelow = nextNumbers(ls, index, "n below", 1, "n below")[0];
    seekKey(ls, "RAT");
    m.specular = nextNumbers(ls, index, "R_sp", 1, "specular reflectance")[0];
    m.diffuse = nextNumbers(ls, index, "R_d", 1, "diffuse reflectance")[0];
    m.absorbed = nextNumbers(ls, index, "A", 1, "absorbed fraction")[0];
    m.transmittance = nextNumbers(ls, index, "T_t", 1, "transmittance")[0];
    m.aLayer = column(ls, "A_l", m.layers.size());
    m.aZ = column(ls, "A_z", size_t(m.nz));
    m.rdR = column(ls, "Rd_r", size_t(m.nr));
    m.rdA = column(ls, "Rd_a", size_t(m.na));
    m.ttR = column(ls, "Tt_r", size_t(m.nr));
    m.ttA = column(ls, "Tt_a", size_t(m.na));
    m.aRz = block(ls, "A_rz", size_t(m.nr) * size_t(m.nz));
    m.rdRa = block(ls, "Rd_ra", size_t(m.nr) * size_t(m.na));
    m.ttRa = block(ls, "Tt_ra", size_t(m.nr) * size_t(m.na));
    return m;
}

McoFile readMco(const std::filesystem::path& file) {
    std::string text;
    try {
        text = core::readFile(file);
    } catch (const core::Error&) {
        throw core::Error(file.string(), 0, "cannot read the file");
    }
    return parseMco(text, file.string());
}

std::string formatMco(const McoFile& m) {
    std::string s = formatted("%s \t# Version number of the file format.\n\n", m.version.c_str());
    s += "####\n# Data categories include: \n# InParm, RAT, \n"
         "# A_l, A_z, Rd_r, Rd_a, Tt_r, Tt_a, \n# A_rz, Rd_ra, Tt_ra \n####\n\n";
    s += m.timeLine + "\n\n";
    s += "InParm \t\t\t# Input parameters. cm is used.\n";
    s += m.outName + " \tA\t\t# output file name, ASCII.\n";
    s += formatted("%lld \t\t\t# No. of photons\n", m.photons);
    s += formatted("%G\t%G\t\t# dz, dr [cm]\n", m.dz, m.dr);
    s += formatted("%d\t%d\t%d\t# No. of dz, dr, da.\n\n", m.nz, m.nr, m.na);
    s += formatted("%d\t\t\t\t\t# Number of layers\n", int(m.layers.size()));
    s += "#n\tmua\tmus\tg\td\t# One line for each layer\n";
    s += formatted("%G\t\t\t\t\t# n for medium above\n", m.nAbove);
    for (size_t k = 0; k < m.layers.size(); ++k) {
        const McoLayer& l = m.layers[k];
        s += formatted("%G\t%G\t%G\t%G\t%G\t# layer %d\n", l.n, l.mua, l.mus, l.g, l.d, int(k + 1));
    }
    s += formatted("%G\t\t\t\t\t# n for medium below\n\n", m.nBelow);
    s += "RAT #Reflectance, absorption, transmission. \n";
    s += formatted("%-14.6G \t#Specular reflectance [-]\n", m.specular);
    s += formatted("%-14.6G \t#Diffuse reflectance [-]\n", m.diffuse);
    s += formatted("%-14.6G \t#Absorbed fraction [-]\n", m.absorbed);
    s += formatted("%-14.6G \t#Transmittance [-]\n", m.transmittance);
    s += "\n";
    s += "A_l #Absorption as a function of layer. [-]\n";
    for (double v : m.aLayer)
        s += formatted("%12.4G\n", v);
    s += "\n";
    auto column = [&](const char* head, const std::vector<double>& v) {
        s += head;
        for (double x : v)
            s += formatted("%12.4E\n", x);
        s += "\n";
    };
    column("A_z #A[0], [1],..A[nz-1]. [1/cm]\n", m.aZ);
    column("Rd_r #Rd[0], [1],..Rd[nr-1]. [1/cm2]\n", m.rdR);
    column("Rd_a #Rd[0], [1],..Rd[na-1]. [sr-1]\n", m.rdA);
    column("Tt_r #Tt[0], [1],..Tt[nr-1]. [1/cm2]\n", m.ttR);
    column("Tt_a #Tt[0], [1],..Tt[na-1]. [sr-1]\n", m.ttA);
    auto block = [&](const char* head, const std::vector<double>& v) {
        s += head;
        for (size_t i = 0; i < v.size(); ++i) {
            s += formatted("%12.4E ", v[i]);
            if ((i + 1) % 5 == 0) s += "\n";
        }
        s += "\n";
    };
    block("# A[r][z]. [1/cm3]\n# A[0][0], [0][1],..[0][nz-1]\n# A[1][0], [1][1],..[1][nz-1]\n"
          "# ...\n# A[nr-1][0], [nr-1][1],..[nr-1][nz-1]\nA_rz\n",
          m.aRz);
    block("# Rd[r][angle]. [1/(cm2sr)].\n# Rd[0][0], [0][1],..[0][na-1]\n"
          "# Rd[1][0], [1][1],..[1][na-1]\n# ...\n# Rd[nr-1][0], [nr-1][1],..[nr-1][na-1]\nRd_ra\n",
          m.rdRa);
    block("# Tt[r][angle]. [1/(cm2sr)].\n# Tt[0][0], [0][1],..[0][na-1]\n"
          "# Tt[1][0], [1][1],..[1][na-1]\n# ...\n# Tt[nr-1][0], [nr-1][1],..[nr-1][na-1]\nTt_ra\n",
          m.ttRa);
    return s;
}

McoFile mcoFromSlab(const Medium& med, const SlabSettings& s, const SlabResult& r,
                    const std::string& outName) {
    McoFile m;
    m.timeLine = formatted("# User time: %8.0f sec = %8.2f hr.   bssrdf-workbench slab: the "
                           "semi-infinite slab; A_z and A_rz are not tallied (written as 0)",
                           r.seconds, r.seconds / 3600);
    m.outName = outName;
    m.photons = (long long)r.paths;
    m.nr = int(r.rd.size());
    m.nz = 1;
    m.na = 1;
    m.dr = s.rMaxMm / s.bins / 10; // cm
    m.layers = {{med.eta, med.sigmaA * 10, med.sigmaS * 10, med.g, 1e8}};
    m.dz = m.layers[0].d;
    m.nAbove = m.nBelow = 1;
    m.specular = r.specular;
    m.diffuse = r.totalRd;
    m.absorbed = r.absorbed;
    m.transmittance = 0;
    m.aLayer = {r.absorbed};
    m.aZ = {0};
    const double pi = 3.1415926, da = 0.5 * pi; // MCML's PI and its one angle bin
    for (double v : r.rd)
        m.rdR.push_back(v * 100); // 1/mm² → 1/cm²
    m.rdA = {r.totalRd / (2 * pi * da * std::sin(0.5 * da))};
    m.ttR.assign(size_t(m.nr), 0.0);
    m.ttA = {0};
    m.aRz.assign(size_t(m.nr), 0.0);
    // MCML scales Rd_ra by 4π² dr² (ir + ½) sin(da/2) sin(2 (ia + ½) da) and Rd_r by
    // 2π dr² (ir + ½): with one angle bin Rd_ra = Rd_r / (2π sin(da/2) sin(da))
    for (double v : m.rdR)
        m.rdRa.push_back(v / (2 * pi * std::sin(0.5 * da) * std::sin(da)));
    m.ttRa.assign(size_t(m.nr), 0.0);
    return m;
}

Medium mediumOfMco(const McoFile& m, const std::string& displayName) {
    if (m.layers.size() != 1)
        throw core::Error(displayName, 0,
                          "a reference profile needs one layer (the semi-infinite slab); the file "
                          "has " +
                              std::to_string(m.layers.size()));
    const McoLayer& l = m.layers[0];
    const double mut = l.mua + l.mus;
    if (!(mut > 0) || l.d * mut < 1000)
        throw core::Error(displayName, 0,
                          "the layer is " + core::formatNumber(l.d * mut, 3) +
                              " mean free paths thick: too thin to stand for the semi-infinite "
                              "slab (at least 1000)");
    if (!(l.mus > 0)) throw core::Error(displayName, 0, "the layer does not scatter (mus = 0)");
    return {l.mua / 10, l.mus / 10, l.g, l.n / m.nAbove};
}

SlabResult slabFromMco(const McoFile& a, const McoFile* b) {
    SlabResult r;
    const size_t n = a.rdR.size() > 0 ? a.rdR.size() - 1 : 0; // the overflow bin left out
    r.paths = uint64_t(a.photons + (b ? b->photons : 0));
    r.specular = a.specular;
    for (size_t i = 0; i < n; ++i) {
        r.rMid.push_back((double(i) + 0.5) * a.dr * 10);
        const double va = a.rdR[i] / 100, vb = b ? b->rdR[i] / 100 : va;
        r.rd.push_back(0.5 * (va + vb));
        r.rdStderr.push_back(0.5 * std::abs(va - vb));
    }
    r.totalRd = b ? 0.5 * (a.diffuse + b->diffuse) : a.diffuse;
    r.totalRdStderr = b ? 0.5 * std::abs(a.diffuse - b->diffuse) : 0;
    r.absorbed = b ? 0.5 * (a.absorbed + b->absorbed) : a.absorbed;
    return r;
}

} // namespace pathtrace
