// core log: thread-safe bounded in-memory log, mirrored to stderr above an echo level; the
// progress line on stderr that the log's echo (and a command's error) first ends: rewritten in
// place on a terminal, a line at a time (throttled) in a file or a CI log.
#include "core.h"

#include <cctype>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <deque>
#include <mutex>
#include <string>

#include <unistd.h>

namespace core {
namespace {
std::mutex g_mutex;
std::deque<LogEntry> g_entries;
LogLevel g_echo = LogLevel::Warn;
constexpr size_t kMaxEntries = 4000;
const auto g_start = std::chrono::steady_clock::now();

std::mutex g_progressMutex;
ProgressMode g_progressMode = ProgressMode::Auto;
bool g_progressOpen = false;
size_t g_progressWidth = 0; // characters the open line shows
// Lines: the last line printed, its phase and time, and a newer line not printed yet
std::string g_progressPhase, g_progressPending;
std::chrono::steady_clock::time_point g_progressPrinted;

bool inPlace() {
    if (g_progressMode == ProgressMode::Auto)
        g_progressMode = isatty(fileno(stderr)) ? ProgressMode::InPlace : ProgressMode::Lines;
    return g_progressMode == ProgressMode::InPlace;
}

// A progress line without its numbers and spaces: "slab:%paths/s" for "slab:  12.5%  3e+05
// paths/s" (an exponent's e included). Lines of one phase differ only in their numbers.
std::string phaseOf(const std::string& text) {
    const auto digit = [&](size_t i) {
        return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]));
    };
    std::string out;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const bool exponent =
            (c == 'e' || c == 'E') && i > 0 && (digit(i - 1)) &&
            (digit(i + 1) || ((i + 1 < text.size()) && (text[i + 1] == '+' || text[i + 1] == '-')));
        if (!digit(i) && !exponent && c != '.' && c != ' ' && c != '+' && c != '-') out += c;
    }
    return out;
}

void printLine(const std::string& text) {
    std::fprintf(stderr, "%s\n", text.c_str());
    std::fflush(stderr);
    g_progressPhase = phaseOf(text);
    g_progressPrinted = std::chrono::steady_clock::now();
    g_progressPending.clear();
}
} // namespace

void setProgressMode(ProgressMode mode) {
    std::lock_guard lock(g_progressMutex);
    g_progressMode = mode;
    g_progressPhase.clear();
    g_progressPending.clear();
}

void progress(const char* fmt, ...) {
    char text[512];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    const size_t n = std::strlen(text);
    std::lock_guard lock(g_progressMutex);
    if (!inPlace()) {
        // a line each: at once for a new phase, else at most every kProgressLineSeconds (the
        // newest of the lines between is printed when the run ends)
        const double since =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - g_progressPrinted)
                .count();
        if (phaseOf(text) != g_progressPhase) {
            // where the last phase ended, then the new one
            if (!g_progressPending.empty()) printLine(g_progressPending);
            printLine(text);
        } else if (since >= kProgressLineSeconds) {
            printLine(text);
        } else {
            g_progressPending = text;
        }
        return;
    }
    // spaces over what the last line showed beyond this one
    const int pad = g_progressWidth > n ? int(g_progressWidth - n) : 0;
    std::fprintf(stderr, "\r%s%*s", text, pad, "");
    std::fflush(stderr);
    g_progressOpen = true;
    g_progressWidth = n;
}

void progressEnd() {
    std::lock_guard lock(g_progressMutex);
    if (!g_progressPending.empty()) printLine(g_progressPending); // where the run ended
    g_progressPhase.clear();
    if (!g_progressOpen) return;
    std::fputc('\n', stderr);
    std::fflush(stderr);
    g_progressOpen = false;
    g_progressWidth = 0;
}

double secondsSinceStart() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count();
}

const char* logLevelName(LogLevel level) {
    switch (level) {
    case LogLevel::Debug:
        return "debug";
    case LogLevel::Info:
        return "info";
    case LogLevel::Warn:
        return "warning";
    case LogLevel::Error:
        return "error";
    }
    return "?";
}

void log(LogLevel level, std::string text) {
    std::lock_guard lock(g_mutex);
    if (level >= g_echo) {
        progressEnd();
        std::fprintf(stderr, "[%s] %s\n", logLevelName(level), text.c_str());
    }
    g_entries.push_back({level, std::move(text), secondsSinceStart()});
    if (g_entries.size() > kMaxEntries) g_entries.pop_front();
}

std::vector<LogEntry> logSnapshot() {
    std::lock_guard lock(g_mutex);
    return {g_entries.begin(), g_entries.end()};
}

void logClear() {
    std::lock_guard lock(g_mutex);
    g_entries.clear();
}

void setLogEchoLevel(LogLevel minLevel) {
    std::lock_guard lock(g_mutex);
    g_echo = minLevel;
}

} // namespace core
