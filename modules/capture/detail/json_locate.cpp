// A forgiving JSON scanner that walks a path of keys/indices to a value's byte offset.
#include "json_locate.h"

namespace capture::detail {

std::string describe(const JsonPath& path) {
    std::string out;
    for (const JsonStep& step : path) {
        if (step.isIndex) {
            out += '[';
            out += std::to_string(step.index);
            out += ']';
        } else {
            if (!out.empty()) out += ".";
            out += step.key;
        }
    }
    return out;
}

namespace {

bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}
bool endsScalar(char c) {
    return isSpace(c) || c == ',' || c == '}' || c == ']';
}

class Scanner {
  public:
    explicit Scanner(std::string_view text) : m_s(text) {}
    size_t pos() const { return m_i; }

    void skipSpace() {
        while (m_i < m_s.size() && isSpace(m_s[m_i]))
            ++m_i;
    }
    // Skips whitespace, then consumes `c` if it is next.
    bool take(char c) {
        skipSpace();
        if (m_i < m_s.size() && m_s[m_i] == c) {
            ++m_i;
            return true;
        }
        return false;
    }
    // Reads a string at the cursor; common escapes are decoded, \uXXXX is kept verbatim.
    bool readString(std::string& out) {
        if (!take('"')) return false;
        while (m_i < m_s.size()) {
            char c = m_s[m_i++];
            if (c == '"') return true;
            if (c != '\\') {
                out += c;
                continue;
            }
            if (m_i >= m_s.size()) return false;
            char e = m_s[m_i++];
            switch (e) {
            case 'n':
                out += '\n';
                break;
            case 't':
                out += '\t';
                break;
            case 'r':
                out += '\r';
                break;
            case 'b':
                out += '\b';
                break;
            case 'f':
                out += '\f';
                break;
            case 'u':
                out += "\\u";
                break;
            default:
                out += e;
                break;
            }
        }
        return false;
    }
    bool skipValue() {
        skipSpace();
        if (m_i >= m_s.size()) return false;
        char c = m_s[m_i];
        if (c == '"') {
            std::string ignored;
            return readString(ignored);
        }
        if (c == '{' || c == '[') {
            int depth = 0;
            while (m_i < m_s.size()) {
                char d = m_s[m_i];
                if (d == '"') {
                    std::string ignored;
                    if (!readString(ignored)) return false;
                    continue;
                }
                if (d == '{' || d == '[') ++depth;
                if (d == '}' || d == ']') {
                    if (--depth == 0) {
                        ++m_i;
                        return true;
                    }
                }
                ++m_i;
            }
            return false;
        }
        size_t start = m_i;
        while (m_i < m_s.size() && !endsScalar(m_s[m_i]))
            ++m_i;
        return m_i > start;
    }

  private:
    std::string_view m_s;
    size_t m_i = 0;
};

} // namespace

size_t findJsonValue(std::string_view text, const JsonPath& path) {
    constexpr size_t npos = std::string_view::npos;
    Scanner sc(text);
    for (const JsonStep& step : path) {
        if (step.isIndex) {
            if (!sc.take('[')) return npos;
            for (size_t k = 0; k < step.index; ++k)
                if (!sc.skipValue() || !sc.take(',')) return npos;
            continue;
        }
        if (!sc.take('{')) return npos;
        while (true) {
            std::string key;
            if (!sc.readString(key) || !sc.take(':')) return npos;
            if (key == step.key) break;
            if (!sc.skipValue() || !sc.take(',')) return npos;
        }
    }
    sc.skipSpace();
    return sc.pos() < text.size() ? sc.pos() : npos;
}

} // namespace capture::detail
