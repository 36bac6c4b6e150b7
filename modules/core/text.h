// core/text.h: numbers as text, written one way for the whole project.
//   - formatNumber(v, digits): printf's "%.<digits>g" in the C locale. The readable form of
//     error messages, CLI reports, cache keys and comparison reports; 9 digits (the default)
//     print every float exactly, 6 is what an iostream prints by default, 17 every double.
//   - formatShortest(v): the shortest text that reads back to the same double
//     (std::to_chars, independent of the locale); "nan", "inf", "-inf" for non-finite values.
//     Tables that must read back bit-exactly (capture CSV, plot CSV export) use it.
//   - nearestName(name, candidates): the candidate a mistyped name most likely meant (edit
//     distance), for "did you mean …?" in error messages.
#pragma once

#include <string>
#include <vector>

namespace core {

// "%.<digits>g" of v (digits 1..17); e.g. formatNumber(0.1, 9) == "0.100000001" for a float
// 0.1f, formatNumber(1e-5, 3) == "1e-05".
std::string formatNumber(double v, int digits = 9);

// Shortest round-trip text of v; appended to `out` (no allocation per number in big tables).
void appendShortest(std::string& out, double v);
inline std::string formatShortest(double v) {
    std::string s;
    appendShortest(s, v);
    return s;
}

// The candidate closest to `name` by Levenshtein distance, ignoring ASCII case, when at most
// max(2, |name|/3) edits away; "" otherwise (no suggestion is better than a wrong one).
std::string nearestName(const std::string& name, const std::vector<std::string>& candidates);

} // namespace core
