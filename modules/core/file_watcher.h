// core::FileWatcher — reports files that changed under a set of directories.
// Uses inotify on the directories (not on the files), so editors that save by writing a
// temporary file and renaming it over the original are seen as a change of that name.
// Bursts are debounced: a path is reported once it has been quiet for `debounceMs`, or by the
// poll that reads its events when the last of them completed a write (the writer closed the file,
// renamed a file onto it, deleted it or changed its mode): a save is seen by the next frame instead
// of after the debounce, while a file still open for writing waits for its close or the quiet.
// When inotify is unavailable it falls back to polling modification times.
// A loop that sleeps between frames (the windowed GUI's glfwWaitEventsTimeout) is woken when events
// arrive: setWake starts a thread that waits on the inotify descriptor (and an eventfd to stop it).
#pragma once

#include <condition_variable>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
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
    // Calls `wake` from a thread of its own whenever events arrive that poll() has not read yet,
    // once per arrival (it waits for poll() to read them before it waits for more). `wake` must be
    // safe to call from any thread (glfwPostEmptyEvent is). Without inotify it is never called.
    void setWake(std::function<void()> wake);

  private:
    void addWatches(const std::filesystem::path& dir);
    void drainInotify();
    void scanPolling();
    void rewatchReappeared(double nowMs); // folders of m_dirs deleted and created again
    void wakeLoop();
    void stopWake();

    std::vector<std::filesystem::path> m_dirs;
    double m_debounceMs;
    int m_fd = -1;
    std::map<int, std::filesystem::path> m_wdToDir;
    struct Pending {
        double lastMs = 0;     // time of the path's last event
        bool complete = false; // that event completed a write (inotify only)
    };
    std::map<std::filesystem::path, Pending> m_pending;
    std::map<std::filesystem::path, long long> m_pollStamp; // polling fallback
    double m_lastScanMs = -1e9;
    double m_lastRewatchMs = -1e9;
    // setWake's thread: it waits for m_fd to be readable, calls m_wake, then waits until
    // drainInotify has read (m_drained) before it waits for the descriptor again.
    std::function<void()> m_wake;
    std::thread m_wakeThread;
    int m_stopFd = -1;
    std::mutex m_wakeMutex;
    std::condition_variable m_wakeCv;
    bool m_drained = false, m_stopping = false;
};

} // namespace core
