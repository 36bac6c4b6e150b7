// core::FileWatcher — inotify on directories with debounce (shorter after a completed write),
// polling fallback. A watched folder that is deleted (its watch ends with IN_IGNORED) is looked for
// again every 250 ms; when it reappears it is watched again and every file in it reported, since
// files written before the new watch raised no event.
#include "file_watcher.h"

#include "core.h"

#include <algorithm>
#include <cerrno>
#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/inotify.h>
#include <unistd.h>

namespace core {
namespace fs = std::filesystem;

namespace {
double nowMs() {
    return secondsSinceStart() * 1000.0;
}
// Writes, renames, creations, deletions, and a changed mode (IN_ATTRIB: a model made unreadable,
// or readable again, is read again).
constexpr uint32_t kWatchMask = IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE |
                                IN_DELETE | IN_MODIFY | IN_DELETE_SELF | IN_ATTRIB;
// Events after which the file's content is whole: a write closed, a file renamed onto the name or
// away from it, a deletion, a mode change. A creation or a write of a file still open is not.
constexpr uint32_t kCompleteMask =
    IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_DELETE | IN_ATTRIB;
// Editor temporaries and our own atomic-write temporaries are not model files.
bool ignoredName(const std::string& name) {
    return name.empty() || name[0] == '.' || name.back() == '~' || name.ends_with(".tmp") ||
           name.ends_with(".swp");
}
} // namespace

FileWatcher::FileWatcher(std::vector<fs::path> dirs, double debounceMs)
    : m_dirs(std::move(dirs)), m_debounceMs(debounceMs) {
    m_fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (m_fd < 0) {
        logWarn("inotify unavailable, polling files for changes instead");
        scanPolling();
        return;
    }
    for (auto& d : m_dirs)
        addWatches(d);
}

FileWatcher::~FileWatcher() {
    stopWake();
    if (m_fd >= 0) close(m_fd);
}

void FileWatcher::setWake(std::function<void()> wake) {
    stopWake();
    if (m_fd < 0 || !wake) return;
    m_stopFd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (m_stopFd < 0) {
        logWarn("cannot wait for file changes between frames (eventfd failed); they are seen at "
                "the next frame");
        return;
    }
    m_wake = std::move(wake);
    m_stopping = false;
    m_wakeThread = std::thread([this] { wakeLoop(); });
}

void FileWatcher::stopWake() {
    if (!m_wakeThread.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(m_wakeMutex);
        m_stopping = true;
    }
    const uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = write(m_stopFd, &one, sizeof one);
    m_wakeCv.notify_all();
    m_wakeThread.join();
    close(m_stopFd);
    m_stopFd = -1;
}

void FileWatcher::wakeLoop() {
    for (;;) {
        {
            std::lock_guard<std::mutex> lock(m_wakeMutex);
            if (m_stopping) return;
            m_drained = false; // a read before this point was of earlier events
        }
        pollfd fds[2] = {{m_fd, POLLIN, 0}, {m_stopFd, POLLIN, 0}};
        if (::poll(fds, 2, -1) < 0) {
            if (errno == EINTR) continue;
            return;
        }
        if (fds[1].revents != 0) return;
        if ((fds[0].revents & POLLIN) == 0) continue;
        m_wake();
        std::unique_lock<std::mutex> lock(m_wakeMutex);
        m_wakeCv.wait(lock, [this] { return m_drained || m_stopping; });
    }
}

void FileWatcher::addWatches(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    int wd = inotify_add_watch(m_fd, dir.c_str(), kWatchMask);
    if (wd >= 0) m_wdToDir[wd] = dir;
    for (auto& e : fs::directory_iterator(dir, ec))
        if (e.is_directory(ec)) addWatches(e.path());
}

void FileWatcher::watch(const fs::path& dir) {
    for (const auto& [wd, d] : m_wdToDir)
        if (d == dir) return;
    if (std::find(m_dirs.begin(), m_dirs.end(), dir) != m_dirs.end()) return;
    if (m_fd < 0) {
        m_dirs.push_back(dir);
        return;
    }
    const int wd = inotify_add_watch(m_fd, dir.c_str(), kWatchMask);
    if (wd >= 0)
        m_wdToDir[wd] = dir;
    else
        logWarn("cannot watch " + dir.string() + " for changes");
}

void FileWatcher::drainInotify() {
    alignas(inotify_event) char buf[16384];
    for (;;) {
        ssize_t n = read(m_fd, buf, sizeof buf);
        if (n <= 0) break;
        for (char* p = buf; p < buf + n;) {
            auto* ev = reinterpret_cast<inotify_event*>(p);
            p += sizeof(inotify_event) + ev->len;
            auto it = m_wdToDir.find(ev->wd);
            if (it == m_wdToDir.end()) continue;
            if (ev->mask & IN_IGNORED) { // the folder was deleted (or unmounted)
                m_wdToDir.erase(it);
                continue;
            }
            if (ev->len == 0) continue;
            fs::path path = it->second / ev->name;
            if (ignoredName(ev->name)) continue;
            if ((ev->mask & IN_ISDIR) && (ev->mask & (IN_CREATE | IN_MOVED_TO))) addWatches(path);
            m_pending[path] = {nowMs(), (ev->mask & kCompleteMask) != 0};
        }
    }
    if (m_wakeThread.joinable()) {
        std::lock_guard<std::mutex> lock(m_wakeMutex);
        m_drained = true;
        m_wakeCv.notify_all();
    }
}

void FileWatcher::scanPolling() {
    std::map<fs::path, long long> now;
    std::error_code ec;
    for (auto& d : m_dirs)
        for (auto it = fs::recursive_directory_iterator(d, ec);
             !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
            if (!it->is_regular_file(ec)) continue;
            auto t = fs::last_write_time(it->path(), ec);
            now[it->path()] = t.time_since_epoch().count();
        }
    const double t = nowMs();
    for (auto& [p, s] : now) {
        auto it = m_pollStamp.find(p);
        if (it == m_pollStamp.end() || it->second != s) m_pending[p] = {t, false};
    }
    for (auto& [p, s] : m_pollStamp)
        if (!now.count(p)) m_pending[p] = {t, false};
    m_pollStamp = std::move(now);
}

void FileWatcher::rewatchReappeared(double t) {
    if (t - m_lastRewatchMs < 250.0) return;
    m_lastRewatchMs = t;
    for (const fs::path& d : m_dirs) {
        bool watched = false;
        for (const auto& [wd, w] : m_wdToDir)
            watched |= w == d;
        std::error_code ec;
        if (watched || !fs::is_directory(d, ec)) continue;
        addWatches(d);
        for (auto it = fs::recursive_directory_iterator(d, ec);
             !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
            if (it->is_regular_file(ec) && !ignoredName(it->path().filename().string()))
                m_pending[it->path()] = {t, false};
    }
}

std::vector<fs::path> FileWatcher::poll() {
    const double t = nowMs();
    if (m_fd >= 0) {
        drainInotify();
        rewatchReappeared(t);
    } else if (t - m_lastScanMs > 250.0) {
        bool first = m_lastScanMs < -1e8;
        m_lastScanMs = t;
        scanPolling();
        if (first) m_pending.clear();
    }
    std::vector<fs::path> settled;
    for (auto it = m_pending.begin(); it != m_pending.end();) {
        if (it->second.complete || t - it->second.lastMs >= m_debounceMs) {
            settled.push_back(it->first);
            it = m_pending.erase(it);
        } else {
            ++it;
        }
    }
    return settled;
}

} // namespace core
