// core log: thread-safe bounded in-memory log, mirrored to stderr above an echo level.
#include "core.h"

#include <cstdio>
#include <deque>
#include <mutex>

namespace core {
namespace {
std::mutex g_mutex;
std::deque<LogEntry> g_entries;
LogLevel g_echo = LogLevel::Warn;
constexpr size_t kMaxEntries = 4000;
const auto g_start = std::chrono::steady_clock::now();
} // namespace

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
    if (level >= g_echo) std::fprintf(stderr, "[%s] %s\n", logLevelName(level), text.c_str());
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
