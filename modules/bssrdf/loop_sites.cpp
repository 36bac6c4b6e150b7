// Loop statements of a model's GLSL (loop_sites.h).
#include "bssrdf/loop_sites.h"

#include <algorithm>
#include <cctype>

namespace bssrdf {

namespace {

bool identChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

} // namespace

void forEachWord(const std::string& c, int firstLine,
                 const std::function<void(const std::string&, size_t, int, char)>& onWord) {
    bool inComment = false;
    int line = firstLine;
    char lastCode = 0; // the last character of code outside comments, across lines
    for (size_t i = 0; i < c.size(); ++i) {
        if (c[i] == '\n') {
            ++line;
            continue;
        }
        if (inComment) {
            if (c[i] == '*' && i + 1 < c.size() && c[i + 1] == '/') {
                inComment = false;
                ++i;
            }
            continue;
        }
        if (c[i] == '/' && i + 1 < c.size() && c[i + 1] == '/') { // to the end of the line
            while (i + 1 < c.size() && c[i + 1] != '\n')
                ++i;
            continue;
        }
        if (c[i] == '/' && i + 1 < c.size() && c[i + 1] == '*') {
            inComment = true;
            ++i;
            continue;
        }
        if (c[i] == '#' && (i == 0 || c[i - 1] == '\n')) { // a preprocessor line
            while (i + 1 < c.size() && c[i + 1] != '\n')
                ++i;
            continue;
        }
        if (identChar(c[i]) && (i == 0 || !identChar(c[i - 1]))) {
            size_t j = i;
            while (j < c.size() && identChar(c[j]))
                ++j;
            onWord(c.substr(i, j - i), i, line, lastCode);
            lastCode = c[j - 1];
            i = j - 1;
            continue;
        }
        if (!std::isspace(static_cast<unsigned char>(c[i]))) lastCode = c[i];
    }
}

namespace {
// Appends the loops of one section (the `while` that closes a `do` block is the `do`'s).
void scan(const Section& s, std::vector<LoopSite>& out) {
    forEachWord(s.code, s.firstLine, [&](const std::string& word, size_t, int line, char lastCode) {
        const bool closesDo = word == "while" && lastCode == '}';
        if ((word == "for" || word == "while" || word == "do") && !closesDo)
            out.push_back({line, word});
    });
}

} // namespace

void forEachDefine(const std::string& code, int firstLine,
                   const std::function<void(const std::string& text, int line)>& onDefine) {
    int line = firstLine;
    for (size_t at = 0; at < code.size();) {
        const int start = line;
        std::string text;
        size_t end = at;
        for (;;) { // one logical line: a trailing backslash continues it
            end = std::min(code.find('\n', at), code.size());
            text += code.substr(at, end - at);
            if (text.empty() || text.back() != '\\' || end >= code.size()) break;
            text.pop_back();
            at = end + 1;
            ++line;
        }
        at = end + 1;
        ++line;
        size_t i = text.find_first_not_of(" \t");
        if (i == std::string::npos || text[i] != '#') continue;
        i = text.find_first_not_of(" \t", i + 1);
        if (i == std::string::npos || text.compare(i, 6, "define") != 0) continue;
        onDefine(text, start);
    }
}

int loopInMacro(const std::string& code, int firstLine) {
    int found = 0;
    forEachDefine(code, firstLine, [&](std::string text, int line) {
        if (found) return;
        text = text.substr(0, text.find("//"));
        if (text.find("##") != std::string::npos) found = line;
        for (size_t w = 0; w < text.size() && !found; ++w) {
            if (!identChar(text[w]) || (w > 0 && identChar(text[w - 1]))) continue;
            size_t e = w;
            while (e < text.size() && identChar(text[e]))
                ++e;
            const std::string word = text.substr(w, e - w);
            if (word == "for" || word == "while" || word == "do") found = line;
            w = e;
        }
    });
    return found;
}

std::vector<LoopSite> loopSites(const Model& m) {
    std::vector<LoopSite> out;
    for (const auto* s : {&m.initializer, &m.diffuseReflectance, &m.shader, &m.sample})
        if (*s) scan(**s, out);
    std::sort(out.begin(), out.end(),
              [](const LoopSite& a, const LoopSite& b) { return a.line < b.line; });
    return out;
}

std::string describeLoops(const std::vector<LoopSite>& loops) {
    if (loops.empty()) return "";
    std::string s = loops.size() == 1 ? "the loop at line " : "loops at lines ";
    for (size_t i = 0; i < loops.size() && i < 6; ++i)
        s += (i ? ", " : "") + std::to_string(loops[i].line) + " (" + loops[i].keyword + ")";
    if (loops.size() > 6) s += " and " + std::to_string(loops.size() - 6) + " more";
    return s;
}

} // namespace bssrdf
