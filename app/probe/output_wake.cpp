// Waking a sleeping frame loop on a child's output (output_wake.h): one epoll set, edge-triggered,
// of every child's output pipe, and a thread that waits on it while a wake function is set.
#include "probe/output_wake.h"

#include "core/core.h"

#include <cerrno>
#include <mutex>
#include <thread>

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <unistd.h>

namespace app {
namespace {

struct OutputWake {
    std::mutex mutex;
    int epoll = -1; // made at the first child or wake; kept for the life of the process
    bool failed = false;
    int stopFd = -1; // in the set while the thread runs
    std::thread thread;

    int epollFd() { // with the mutex held
        if (epoll < 0 && !failed) {
            epoll = epoll_create1(EPOLL_CLOEXEC);
            if (epoll < 0) {
                failed = true;
                core::logWarn("cannot wait for child processes' output between frames (epoll "
                              "failed); it is read at the next frame");
            }
        }
        return epoll;
    }

    void stop() { // with the mutex held
        if (!thread.joinable()) return;
        const uint64_t one = 1;
        [[maybe_unused]] const ssize_t n = write(stopFd, &one, sizeof one);
        thread.join();
        epoll_ctl(epoll, EPOLL_CTL_DEL, stopFd, nullptr);
        close(stopFd);
        stopFd = -1;
    }

    static void loop(int ep, int stopFd, const std::function<void()>& wake) {
        epoll_event events[16];
        for (;;) {
            const int n = epoll_wait(ep, events, 16, -1);
            if (n < 0) {
                if (errno == EINTR) continue;
                return;
            }
            bool output = false;
            for (int i = 0; i < n; ++i) {
                if (events[i].data.fd == stopFd) return;
                output = true;
            }
            if (output) wake();
        }
    }
};

// Never destroyed: a child held by a static (the warm probe server) may end after other statics.
OutputWake& state() {
    static OutputWake* s = new OutputWake;
    return *s;
}

} // namespace

void wakeOnChildOutput(std::function<void()> wake) {
    OutputWake& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    s.stop();
    if (!wake || s.epollFd() < 0) return;
    s.stopFd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    epoll_event e{};
    e.events = EPOLLIN; // level-triggered: it stays readable until the thread has ended
    e.data.fd = s.stopFd;
    if (s.stopFd < 0 || epoll_ctl(s.epoll, EPOLL_CTL_ADD, s.stopFd, &e) != 0) {
        if (s.stopFd >= 0) close(s.stopFd);
        s.stopFd = -1;
        core::logWarn("cannot wait for child processes' output between frames (eventfd failed); "
                      "it is read at the next frame");
        return;
    }
    s.thread = std::thread(OutputWake::loop, s.epoll, s.stopFd, std::move(wake));
}

namespace detail {

void watchChildOutput(int fd) {
    OutputWake& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    if (s.epollFd() < 0) return;
    epoll_event e{};
    // edge-triggered: one event when data arrives (or the child ends), not one per wait while
    // it is still unread
    e.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
    e.data.fd = fd;
    epoll_ctl(s.epoll, EPOLL_CTL_ADD, fd, &e);
}

void unwatchChildOutput(int fd) {
    OutputWake& s = state();
    std::lock_guard<std::mutex> lock(s.mutex);
    if (s.epoll >= 0) epoll_ctl(s.epoll, EPOLL_CTL_DEL, fd, nullptr);
}

} // namespace detail
} // namespace app
