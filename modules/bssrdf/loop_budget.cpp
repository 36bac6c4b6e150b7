// The model's loop budget (loop_budget.h): the rewrite of its loop conditions, the GLSL around
// it and the host's counters.
#include "bssrdf/loop_budget.h"

#include "bssrdf/loop_sites.h"
#include "core/core.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>

namespace bssrdf {

namespace {

constexpr int kCounters = 8; // [0]: invocations stopped; [1 + min(site, 6)]: by the loop's site

// The index of the `)` closing the `(` at `open`, or npos.
size_t closing(const std::string& c, size_t open) {
    int depth = 0;
    for (size_t i = open; i < c.size(); ++i) {
        if (c[i] == '(') ++depth;
        if (c[i] == ')' && --depth == 0) return i;
    }
    return std::string::npos;
}

bool blank(const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char ch) { return std::isspace((unsigned char)ch); });
}

} // namespace

unsigned loopBudget() {
    const char* s = std::getenv("BSSRDF_WORKBENCH_LOOP_BUDGET");
    if (!s || !*s) return kLoopBudget;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(s, &end, 10);
    if (end == s || *end != '\0' || v < 1 || v > (1ull << 31) || s[0] == '-')
        throw core::Error("BSSRDF_WORKBENCH_LOOP_BUDGET", 0,
                          "'" + std::string(s) + "' is not a loop budget (1 to 2147483648)");
    return static_cast<unsigned>(v);
}

std::string guardLoops(const std::string& c, int firstLine, unsigned& site,
                       std::vector<int>& lines) {
    std::string out;
    size_t copied = 0;
    forEachWord(c, firstLine, [&](const std::string& word, size_t at, int line, char) {
        if (word != "for" && word != "while") return;
        size_t open = at + word.size();
        while (open < c.size() && std::isspace(static_cast<unsigned char>(c[open])))
            ++open;
        const size_t close =
            open < c.size() && c[open] == '(' ? closing(c, open) : std::string::npos;
        if (close == std::string::npos || open < copied) return; // not a header to guard
        size_t from = open + 1, to = close;                      // the condition
        if (word == "for") {
            int depth = 0;
            std::vector<size_t> semis;
            for (size_t k = open + 1; k < close; ++k) {
                if (c[k] == '(') ++depth;
                if (c[k] == ')') --depth;
                if (c[k] == ';' && depth == 0) semis.push_back(k);
            }
            if (semis.size() != 2) return;
            from = semis[0] + 1;
            to = semis[1];
        }
        const std::string guard = "bw_loop(" + std::to_string(site) + "u)";
        const std::string condition = c.substr(from, to - from);
        out += c.substr(copied, from - copied);
        out += blank(condition) ? condition + guard : "(" + condition + ") && " + guard;
        copied = to;
        lines.push_back(line);
        ++site;
    });
    out += c.substr(copied);
    return out;
}

std::vector<int> guardedLoopLines(const Model& m) {
    std::vector<int> lines;
    unsigned site = 0;
    for (const auto* s : {&m.initializer, &m.diffuseReflectance, &m.shader, &m.sample})
        if (*s) guardLoops((*s)->code, (*s)->firstLine, site, lines);
    return lines;
}

std::string loopGuardPrelude() {
    return "uniform uint BwLoopBudget;\n"
           "layout(binding = 0, offset = 0) uniform atomic_uint bw_loopFaults[8];\n"
           "uint bw_loopCount = 0u;\n"
           "bool bw_loopStopped = false;\n"
           "bool bw_loop(uint site) {\n"
           "    if (bw_loopStopped) return false;\n"
           "    ++bw_loopCount;\n"
           "    bool over = bw_loopCount > BwLoopBudget;\n"
           "    if (!over && (bw_loopCount & 255u) != 0u) return true;\n"
           "    if (!over && atomicCounter(bw_loopFaults[0]) == 0u) return true;\n"
           "    bw_loopStopped = true;\n"
           "    atomicCounterIncrement(bw_loopFaults[0]);\n"
           "    if (over) atomicCounterIncrement(bw_loopFaults[1u + min(site, 6u)]);\n"
           "    return false;\n"
           "}\n";
}

std::string loopGuardEpilogue(const Model& m) {
    if (!m.shader) return "";
    return "vec3 bw_callBssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
           "    bw_loopCount = 0u;\n"
           "    return Bssrdf(Xi, Wi, Xo, Wo);\n"
           "}\n"
           "#define Bssrdf bw_callBssrdf\n";
}

void LoopFaults::arm(GLuint program) {
    const std::array<GLuint, kCounters> zeros{};
    if (!m_counters)
        m_counters = gl::createBuffer(sizeof zeros, zeros.data());
    else
        glNamedBufferSubData(m_counters.id(), 0, sizeof zeros, zeros.data());
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, m_counters.id());
    if (const GLint loc = glGetUniformLocation(program, "BwLoopBudget"); loc >= 0)
        glProgramUniform1ui(program, loc, loopBudget());
}

void LoopFaults::check(const Model& m) {
    if (!m_counters) return;
    std::array<GLuint, kCounters> counts{};
    // barrier: bw_loop's atomic counters (any model program) → the readback below
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(m_counters.id(), 0, sizeof counts, counts.data());
    if (counts[0] == 0) return;
    const std::vector<int> lines = guardedLoopLines(m);
    size_t site = 0;
    for (size_t k = 1; k < kCounters; ++k)
        if (counts[k] != 0) {
            site = k - 1;
            break;
        }
    const int line = site < lines.size() ? lines[site] : 0;
    const std::string which = site == kCounters - 2 && lines.size() > kCounters - 1
                                  ? "one of the loops from line " + std::to_string(line) + " on"
                                  : "the loop at line " + std::to_string(line);
    throw core::Error(m.path, line,
                      which + " ran past the loop budget of " + std::to_string(loopBudget()) +
                          " iterations per Bssrdf() call (" + std::to_string(counts[0]) +
                          " invocations stopped): a loop that does not end for these inputs?");
}

} // namespace bssrdf
