// core text/file helpers: whole-file IO with clear errors, UTF-8 validation (RFC 3629),
// FNV-1a 64-bit content hashes, numbers as text (text.h).
#include "text.h"
#include "core.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace core {

std::string readFile(const std::filesystem::path& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw Error(path.string(), 0, "is a directory, expected a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path.string(), 0, std::string("cannot open: ") + std::strerror(errno));
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

void writeFile(const std::filesystem::path& path, std::string_view bytes) {
    // Only a regular file (or nothing) is replaced: renaming over /dev/full, a FIFO or a socket
    // would replace the node itself.
    std::error_code statEc;
    const auto st = std::filesystem::status(path, statEc);
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
        throw Error(path.string(), 0, "not a regular file: refusing to replace it");
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    // A file or symlink already at the temporary name (a crashed write, or one planted in an
    // untrusted capture folder) is removed, never written through.
    std::error_code removeEc;
    std::filesystem::remove(tmp, removeEc);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out)
            throw Error(path.string(), 0, std::string("cannot write: ") + std::strerror(errno));
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        out.close(); // a full disk may only show when the last buffer is written
        if (!out) {
            std::filesystem::remove(tmp);
            throw Error(path.string(), 0, "write failed (disk full?)");
        }
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp);
        throw Error(path.string(), 0, "cannot write: " + ec.message());
    }
}

std::optional<size_t> firstInvalidUtf8(std::string_view s) {
    size_t i = 0;
    const size_t n = s.size();
    while (i < n) {
        unsigned char c = static_cast<unsigned char>(s[i]);
        if (c == 0) return i; // NUL bytes mean binary data, not text
        if (c < 0x80) {
            ++i;
            continue;
        }
        int len = 0;
        uint32_t cp = 0;
        if ((c & 0xE0) == 0xC0)
            len = 2, cp = c & 0x1F;
        else if ((c & 0xF0) == 0xE0)
            len = 3, cp = c & 0x0F;
        else if ((c & 0xF8) == 0xF0)
            len = 4, cp = c & 0x07;
        else
            return i;
        if (i + len > n) return i;
        for (int k = 1; k < len; ++k) {
            unsigned char cc = static_cast<unsigned char>(s[i + k]);
            if ((cc & 0xC0) != 0x80) return i;
            cp = (cp << 6) | (cc & 0x3F);
        }
        // reject overlong forms, surrogates and values past U+10FFFF
        if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000) ||
            (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF)
            return i;
        i += len;
    }
    return std::nullopt;
}

namespace {
// Length of the valid UTF-8 sequence starting at s[i] (a byte >= 0x80), or 0 when it is not one.
size_t utf8SequenceAt(std::string_view s, size_t i) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    if (len == 0 || i + len > s.size()) return 0;
    return firstInvalidUtf8(s.substr(i, len)) ? 0 : len;
}

bool plainByte(unsigned char c) {
    return (c >= 0x20 && c < 0x7F) || c == '\n' || c == '\t';
}
} // namespace

std::string printableText(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    size_t i = 0;
    while (i < text.size()) {
        unsigned char c = static_cast<unsigned char>(text[i]);
        if (plainByte(c)) {
            out += char(c);
            ++i;
            continue;
        }
        size_t len = c >= 0x80 ? utf8SequenceAt(text, i) : 0;
        if (len > 0) {
            out.append(text.substr(i, len));
            i += len;
            continue;
        }
        static const char kHex[] = "0123456789abcdef";
        out += "\\x";
        out += kHex[c >> 4];
        out += kHex[c & 15];
        ++i;
    }
    return out;
}

bool isPrintableText(std::string_view text) {
    size_t i = 0;
    while (i < text.size()) {
        unsigned char c = static_cast<unsigned char>(text[i]);
        size_t len = plainByte(c) ? 1 : c >= 0x80 ? utf8SequenceAt(text, i) : 0;
        if (len == 0) return false;
        i += len;
    }
    return true;
}

int lineOfOffset(std::string_view text, size_t offset) {
    int line = 1;
    for (size_t i = 0; i < offset && i < text.size(); ++i)
        if (text[i] == '\n') ++line;
    return line;
}

uint64_t fnv1a64(std::string_view bytes) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

std::string hashHex(std::string_view bytes) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(fnv1a64(bytes)));
    return std::string("fnv1a64:") + buf;
}

std::string formatNumber(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

void appendShortest(std::string& out, double v) {
    if (std::isnan(v)) { // to_chars would write "-nan" for a negative NaN
        out += "nan";
        return;
    }
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, v);
    (void)res.ec; // 64 bytes always suffice for the shortest form of a double
    out.append(buf, res.ptr);
}

std::string relativeTo(const std::filesystem::path& p, const std::filesystem::path& base) {
    std::error_code ec;
    auto ap = std::filesystem::weakly_canonical(p, ec);
    auto ab = std::filesystem::weakly_canonical(base, ec);
    auto rel = ap.lexically_relative(ab);
    if (!rel.empty() && *rel.begin() != "..") return rel.generic_string();
    return p.generic_string();
}

// Levenshtein distance by the two-row dynamic programme, written here because no Debian package
// the project uses offers one for plain strings.
std::string nearestName(const std::string& name, const std::vector<std::string>& candidates) {
    auto lower = [](std::string t) {
        for (char& c : t)
            if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
        return t;
    };
    const std::string a = lower(name);
    size_t best = std::max<size_t>(2, a.size() / 3) + 1;
    std::string out;
    for (const std::string& candidate : candidates) {
        const std::string b = lower(candidate);
        std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
        for (size_t j = 0; j <= b.size(); ++j)
            prev[j] = j;
        for (size_t i = 1; i <= a.size(); ++i) {
            cur[0] = i;
            for (size_t j = 1; j <= b.size(); ++j)
                cur[j] = std::min(
                    {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            std::swap(prev, cur);
        }
        if (prev[b.size()] < best) {
            best = prev[b.size()];
            out = candidate;
        }
    }
    return out;
}

} // namespace core
