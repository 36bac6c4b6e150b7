// Wakes a loop that sleeps between frames when a child process (child_process.h) writes: the
// windowed GUI waits up to 30 ms for events between frames, so without this a model check's
// verdict, or a replay's progress line, would wait for the end of that sleep before a frame reads
// it. One thread for all children: an epoll set (edge-triggered, so one call per arrival, not one
// per frame while the data waits to be read) of every child's output pipe, and an eventfd that
// stops it. Linux only, as the rest of probe/.
#pragma once

#include <functional>

namespace app {

// Calls `wake` from a thread of its own whenever a child process writes output or ends, from now
// until the next call; an empty function stops it (returning after the thread has ended, so
// `wake` is not called after that). `wake` must be safe to call from any thread
// (glfwPostEmptyEvent is). Without epoll it is never called, and says so once in the log.
void wakeOnChildOutput(std::function<void()> wake);

namespace detail {
// ChildProcess's output pipe joins the set when the child starts and leaves it before the pipe
// is closed.
void watchChildOutput(int fd);
void unwatchChildOutput(int fd);
} // namespace detail

} // namespace app
