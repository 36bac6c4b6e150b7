// core: the small shared layer every module builds on.
//   - Error: the one exception type thrown at parse/load boundaries; it carries the file and
//     line it is about so the app can show "file:line: message" and keep the last good state.
//   - log: a thread-safe in-memory log (shown in the Errors/Log panel) mirrored to stderr.
//   - text files: reading with clear errors, UTF-8 validation, content hashes (FNV-1a 64).
//   - timing: a CPU stopwatch.
// Algorithms: FNV-1a (Fowler/Noll/Vo) for content hashes; UTF-8 validation per RFC 3629.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace core {

// An error at a boundary (file parse, load, compile, CLI argument). line 0 = whole file.
class Error : public std::runtime_error {
  public:
    Error(std::string file, int line, std::string message);
    explicit Error(std::string message) : Error("", 0, std::move(message)) {}
    const std::string& file() const { return m_file; }
    int line() const { return m_line; }
    const std::string& message() const { return m_message; }

  private:
    Error(std::string file, int line, std::string message, int); // already printable
    std::string m_file;
    int m_line;
    std::string m_message;
};

// "file:line: message", "file: message" or "message".
std::string formatLocation(const std::string& file, int line, const std::string& message);

// ---- log --------------------------------------------------------------------------------
enum class LogLevel { Debug, Info, Warn, Error };
struct LogEntry {
    LogLevel level;
    std::string text;
    double seconds; // since program start
};
void log(LogLevel level, std::string text);
inline void logDebug(std::string t) {
    log(LogLevel::Debug, std::move(t));
}
inline void logInfo(std::string t) {
    log(LogLevel::Info, std::move(t));
}
inline void logWarn(std::string t) {
    log(LogLevel::Warn, std::move(t));
}
inline void logError(std::string t) {
    log(LogLevel::Error, std::move(t));
}
std::vector<LogEntry> logSnapshot();
void logClear();
void setLogEchoLevel(LogLevel minLevel); // entries at or above go to stderr (default Warn)
const char* logLevelName(LogLevel level);

// ---- progress lines ---------------------------------------------------------------------------
// A long run's progress: one line on stderr, rewritten in place (printf format, without "\r" or
// padding). Whatever goes to stderr next through here — the log's echo, progressEnd() before a
// command's result or its `error: …` — first ends the line, so no message starts after a
// percentage. Thread-safe (progress callbacks come from worker threads).
// When stderr is not a terminal (a file, a pipe, a CI log) a rewritten line would pile up as one
// line of carriage returns: there each update is a line of its own, printed at once when its
// phase (the text without its numbers) is new and otherwise at most every kProgressLineSeconds;
// progressEnd() prints the newest line not printed yet, so the log shows where the run ended.
void progress(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
void progressEnd(); // ends an open progress line with a newline; nothing when none is open
inline constexpr double kProgressLineSeconds = 5.0;
enum class ProgressMode {
    Auto,    // InPlace when stderr is a terminal at the first progress line, else Lines
    InPlace, // "\r" rewrites
    Lines,   // a line each, throttled
};
void setProgressMode(ProgressMode mode);

// ---- files and text -------------------------------------------------------------------------
// Reads a whole file as bytes; throws Error(path, 0, ...) when it cannot be opened.
std::string readFile(const std::filesystem::path& path);
// Writes atomically (temp file + rename); throws Error(path, 0, ...) naming the reason.
void writeFile(const std::filesystem::path& path, std::string_view bytes);
// Offset of the first byte that breaks UTF-8, or nullopt when the text is valid.
std::optional<size_t> firstInvalidUtf8(std::string_view text);
// `text` with every byte a terminal would not show as text escaped: control characters (other
// than newline and tab), DEL and bytes that break UTF-8 become "\xNN", a backslash stays one.
// Error messages pass through it, so that a message quoting the input never prints raw bytes.
std::string printableText(std::string_view text);
// True when printableText(text) would return `text` unchanged.
bool isPrintableText(std::string_view text);
// 1-based line number of a byte offset.
int lineOfOffset(std::string_view text, size_t offset);

uint64_t fnv1a64(std::string_view bytes);
std::string hashHex(std::string_view bytes); // "fnv1a64:" + 16 lowercase hex digits

// Path of `p` relative to `base` when it lies inside it, else p unchanged (generic form).
std::string relativeTo(const std::filesystem::path& p, const std::filesystem::path& base);

// ---- timing -----------------------------------------------------------------------------------
class Stopwatch {
  public:
    Stopwatch() : m_start(std::chrono::steady_clock::now()) {}
    void reset() { m_start = std::chrono::steady_clock::now(); }
    double ms() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start)
            .count();
    }

  private:
    std::chrono::steady_clock::time_point m_start;
};
double secondsSinceStart();

} // namespace core
