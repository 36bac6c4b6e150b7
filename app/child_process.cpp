// Child processes (child_process.h): fork/exec with stdout and stderr on a non-blocking pipe,
// reaped with waitpid(WNOHANG).
#include "child_process.h"

#include "core/core.h"

#include <csignal>
#include <fcntl.h>
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

ChildProcess::ChildProcess(const std::vector<std::string>& argsIn, const std::string& what) {
    std::vector<std::string> args = argsIn;
    std::vector<char*> argv;
    for (auto& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw core::Error(what, 0, "cannot start a process (pipe)");
    m_pid = ::fork();
    if (m_pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        throw core::Error(what, 0, "cannot start a process (fork)");
    }
    if (m_pid == 0) {
        ::dup2(fds[1], STDOUT_FILENO);
        ::dup2(fds[1], STDERR_FILENO);
        ::close(fds[0]);
        ::close(fds[1]);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(fds[1]);
    m_fd = fds[0];
    ::fcntl(m_fd, F_SETFL, ::fcntl(m_fd, F_GETFL) | O_NONBLOCK);
}

ChildProcess::~ChildProcess() {
    if (!m_done) cancel();
    if (m_fd >= 0) ::close(m_fd);
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
