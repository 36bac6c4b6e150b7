// core::FileWatcher — reports files that changed under a set of directories.
// Uses inotify on the directories (not on the files), so editors that save by writing a
// temporary file and renaming it over the original are seen as a change of that name.
// Bursts are debounced: a path is reported once it has been quiet for `debounceMs`.
// When inotify is unavailable it falls back to polling modification times.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace core {

class FileWatcher {
  public:
    explicit FileWatcher(std::vector<std::filesystem::path> dirs, double debounceMs = 40.0);
    ~FileWatcher();
    FileWatcher(const FileWatcher&) = delete;
    FileWatcher& operator=(const FileWatcher&) = delete;

    // Non-blocking. Paths (created, modified, renamed onto, deleted) whose burst has settled.
    std::vector<std::filesystem::path> poll();
    // Also watches `dir` itself (not its subfolders), e.g. the folder of a model opened from
    // outside the project; a folder already watched is left as it is.
    void watch(const std::filesystem::path& dir);
    bool usingInotify() const { return m_fd >= 0; }

  private:
    void addWatches(const std::filesystem::path& dir);
    void drainInotify();
    void scanPolling();
    void rewatchReappeared(double nowMs); // folders of m_dirs deleted and created again

    std::vector<std::filesystem::path> m_dirs;
    double m_debounceMs;
    int m_fd = -1;
    std::map<int, std::filesystem::path> m_wdToDir;
    std::map<std::filesystem::path, double> m_pending;      // path -> last event time (ms)
    std::map<std::filesystem::path, long long> m_pollStamp; // polling fallback
    double m_lastScanMs = -1e9;
    double m_lastRewatchMs = -1e9;
};

} // namespace core
