// capture CSV tables: '#' comments, one header row, numbers written shortest-round-trip
// (std::to_chars) so doubles read back bit-exactly and independent of the C locale.
#include "capture.h"

#include "core/core.h"
#include "core/text.h"

#include <charconv>
#include <cmath>
#include <set>

namespace capture {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
        s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> splitFields(std::string_view line) {
    std::vector<std::string_view> out;
    size_t start = 0;
    while (true) {
        size_t comma = line.find(',', start);
        if (comma == std::string_view::npos) {
            out.push_back(trim(line.substr(start)));
            return out;
        }
        out.push_back(trim(line.substr(start, comma - start)));
        start = comma + 1;
    }
}

bool parseNumber(std::string_view field, double& value) {
    if (field.size() > 1 && field.front() == '+' && field[1] != '-') field.remove_prefix(1);
    if (field.empty()) return false;
    const char* end = field.data() + field.size();
    auto [ptr, ec] = std::from_chars(field.data(), end, value);
    return ec == std::errc() && ptr == end;
}

// "" when the name can be written and read back unchanged.
std::string columnNameProblem(const std::string& name) {
    if (name.empty()) return "empty column name";
    if (name.find_first_of(",\r\n") != std::string::npos)
        return "column name '" + name + "' contains ',' or a line break";
    if (name.front() == '#') return "column name '" + name + "' starts with '#'";
    if (trim(name) != name) return "column name '" + name + "' has leading/trailing blanks";
    return "";
}

} // namespace

int Table::columnIndex(std::string_view name) const {
    for (size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return static_cast<int>(i);
    return -1;
}

Table parseCsv(std::string_view text, const std::string& file) {
    Table t;
    bool haveHeader = false;
    int lineNo = 0;
    int blankLine = 0; // first blank line after the header, allowed only at the end
    size_t pos = 0;
    while (pos < text.size()) {
        size_t nl = text.find('\n', pos);
        std::string_view line =
            text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
        ++lineNo;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);

        if (!haveHeader) {
            if (!line.empty() && line.front() == '#') {
                line.remove_prefix(1);
                if (!line.empty() && line.front() == ' ') line.remove_prefix(1);
                t.comments.emplace_back(line);
                continue;
            }
            if (trim(line).empty())
                throw core::Error(file, lineNo, "blank line where the header row was expected");
            std::set<std::string> seen;
            for (std::string_view name : splitFields(line)) {
                if (name.empty()) throw core::Error(file, lineNo, "empty column name in header");
                if (!seen.insert(std::string(name)).second)
                    throw core::Error(file, lineNo,
                                      "column '" + std::string(name) + "' appears twice");
                t.columns.emplace_back(name);
            }
            haveHeader = true;
            continue;
        }
        if (trim(line).empty()) {
            if (blankLine == 0) blankLine = lineNo;
            continue;
        }
        if (blankLine != 0) throw core::Error(file, blankLine, "blank line between rows");
        if (line.front() == '#')
            throw core::Error(file, lineNo, "comment lines are only allowed before the header");
        std::vector<std::string_view> fields = splitFields(line);
        if (fields.size() != t.columns.size())
            throw core::Error(file, lineNo,
                              "row has " + std::to_string(fields.size()) + " values, header has " +
                                  std::to_string(t.columns.size()) + " columns");
        std::vector<double> row(fields.size());
        for (size_t c = 0; c < fields.size(); ++c)
            if (!parseNumber(fields[c], row[c]))
                throw core::Error(file, lineNo,
                                  "column '" + t.columns[c] + "': '" + std::string(fields[c]) +
                                      "' is not a number");
        t.rows.push_back(std::move(row));
    }
    if (!haveHeader) throw core::Error(file, 0, "no header row (empty table file)");
    return t;
}

Table readCsv(const std::filesystem::path& path) {
    return parseCsv(core::readFile(path), path.string());
}

std::string formatCsv(const Table& t) {
    if (t.columns.empty()) throw core::Error("", 0, "table has no columns");
    std::set<std::string> seen;
    for (const std::string& name : t.columns) {
        std::string problem = columnNameProblem(name);
        if (!problem.empty()) throw core::Error("", 0, problem);
        if (!seen.insert(name).second)
            throw core::Error("", 0, "column '" + name + "' appears twice");
    }
    std::string out;
    for (const std::string& c : t.comments) {
        if (c.find_first_of("\r\n") != std::string::npos)
            throw core::Error("", 0, "comment contains a line break: '" + c + "'");
        out += "# " + c + "\n";
    }
    for (size_t i = 0; i < t.columns.size(); ++i)
        out += (i ? "," : "") + t.columns[i];
    out += "\n";
    for (size_t r = 0; r < t.rows.size(); ++r) {
        const std::vector<double>& row = t.rows[r];
        if (row.size() != t.columns.size())
            throw core::Error("", 0,
                              "row " + std::to_string(r + 1) + " has " +
                                  std::to_string(row.size()) + " values, table has " +
                                  std::to_string(t.columns.size()) + " columns");
        for (size_t c = 0; c < row.size(); ++c) {
            if (c) out += ',';
            core::appendShortest(out, row[c]);
        }
        out += '\n';
    }
    return out;
}

void writeCsv(const std::filesystem::path& path, const Table& table) {
    std::string text;
    try {
        text = formatCsv(table);
    } catch (const core::Error& e) {
        throw core::Error(path.string(), 0, e.message());
    }
    core::writeFile(path, text);
}

} // namespace capture
