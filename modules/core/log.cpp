// core log: thread-safe bounded in-memory log, mirrored to stderr above an echo level; the
// progress line on stderr that the log's echo (and a command's error) first ends.
#include "core.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <deque>
#include <mutex>

namespace core {
namespace {
std::mutex g_mutex;
std::deque<LogEntry> g_entries;
LogLevel g_echo = LogLevel::Warn;
constexpr size_t kMaxEntries = 4000;
const auto g_start = std::chrono::steady_clock::now();

std::mutex g_progressMutex;
bool g_progressOpen = false;
size_t g_progressWidth = 0; // characters the open line shows
} // namespace

void progress(const char* fmt, ...) {
    char text[512];
    va_list args;
    va_start(args, fmt);
    std::vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    const size_t n = std::strlen(text);
    std::lock_guard lock(g_progressMutex);
    // spaces over what the last line showed beyond this one
    const int pad = g_progressWidth > n ? int(g_progressWidth - n) : 0;
    std::fprintf(stderr, "\r%s%*s", text, pad, "");
    std::fflush(stderr);
    g_progressOpen = true;
    g_progressWidth = n;
}

void progressEnd() {
    std::lock_guard lock(g_progressMutex);
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
