// Child processes (child_process.h): fork/exec with stdout and stderr on a non-blocking pipe,
// reaped with waitpid(WNOHANG); the pipe wakes a sleeping frame loop (output_wake.h).
#include "probe/child_process.h"

#include "core/core.h"
#include "probe/output_wake.h"

#include <cerrno>
#include <csignal>
#include <fcntl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <vector>

namespace app {
namespace fs = std::filesystem;

fs::path selfExecutable() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path("bssrdf-workbench") : p;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argsIn, const std::string& what,
                           bool input) {
    std::vector<std::string> args = argsIn;
    std::vector<char*> argv;
    for (auto& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw core::Error(what, 0, "cannot start a process (pipe)");
    // stdin: a socket rather than a pipe, so a write to a child that has gone fails with EPIPE
    // (MSG_NOSIGNAL) instead of raising SIGPIPE in the workbench
    int in[2] = {-1, -1};
    if (input && ::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, in) != 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        throw core::Error(what, 0, "cannot start a process (socketpair)");
    }
    m_pid = ::fork();
    if (m_pid < 0) {
        for (int fd : {fds[0], fds[1], in[0], in[1]})
            if (fd >= 0) ::close(fd);
        throw core::Error(what, 0, "cannot start a process (fork)");
    }
    if (m_pid == 0) {
        ::dup2(fds[1], STDOUT_FILENO);
        ::dup2(fds[1], STDERR_FILENO);
        if (input) ::dup2(in[1], STDIN_FILENO);
        // (the originals are close-on-exec; the duplicates are not)
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(fds[1]);
    m_fd = fds[0];
    if (input) {
        ::close(in[1]);
        m_in = in[0];
    }
    ::fcntl(m_fd, F_SETFL, ::fcntl(m_fd, F_GETFL) | O_NONBLOCK);
    detail::watchChildOutput(m_fd);
}

ChildProcess::~ChildProcess() {
    if (!m_done) cancel();
    if (m_fd >= 0) {
        detail::unwatchChildOutput(m_fd);
        ::close(m_fd);
    }
    if (m_in >= 0) ::close(m_in);
}

void ChildProcess::closeInput() {
    if (m_in >= 0) ::close(m_in);
    m_in = -1;
}

bool ChildProcess::send(const std::string& bytes) {
    if (m_in < 0 || m_done) return false;
    for (size_t at = 0; at < bytes.size();) {
        const ssize_t n = ::send(m_in, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += size_t(n);
    }
    return true;
}

bool ChildProcess::poll() {
    if (m_done) return true;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(m_fd, buf, sizeof buf);
        if (n > 0) {
            m_output.append(buf, size_t(n));
            continue;
        }
        break; // EAGAIN (nothing yet) or EOF
    }
    int status = 0;
    if (::waitpid(m_pid, &status, WNOHANG) == m_pid) {
        // the rest of the output, now that the writer is gone
        for (ssize_t n; (n = ::read(m_fd, buf, sizeof buf)) > 0;)
            m_output.append(buf, size_t(n));
        m_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        m_done = true;
        detail::unwatchChildOutput(m_fd); // nothing more to wake for
    }
    return m_done;
}

void ChildProcess::cancel() {
    if (m_done || m_pid <= 0) return;
    ::kill(m_pid, SIGKILL);
    int status = 0;
    ::waitpid(m_pid, &status, 0);
    m_code = 128 + SIGKILL;
    m_done = true;
    m_output += "\n(cancelled)\n";
}

} // namespace app
