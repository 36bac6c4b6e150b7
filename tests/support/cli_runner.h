// Shared by the CLI tests: a temporary folder, and running the real bssrdf-workbench executable
// (BW_EXE, with --root BW_SOURCE_ROOT) in a folder with fork/exec, capturing its output.
#pragma once

#include <atomic>
#include <cerrno>
#include <filesystem>

#include <fstream>
#include <gtest/gtest.h>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace clitest {
namespace fs = std::filesystem;

class TempDir {
  public:
    explicit TempDir(const std::string& tag = "test") {
        static std::atomic<int> counter{0};
        std::random_device rd;
        m_path = fs::temp_directory_path() /
                 (std::string("bw_cli_") + tag + "_" + std::to_string(::getpid()) + "_" +
                  std::to_string(counter++) + "_" + std::to_string(rd()));
        fs::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const fs::path& path() const { return m_path; }

  private:
    fs::path m_path;
};

struct RunResult {
    int code = -1;      // exit status, or 128 + signal number
    std::string output; // stdout and stderr interleaved
};

inline std::string describe(const std::vector<std::string>& args, const RunResult& r) {
    std::string s = "command: bssrdf-workbench";
    for (const auto& a : args)
        s += " " + a;
    s += "\nexit code: " + std::to_string(r.code) + "\noutput:\n" + r.output;
    return s;
}

// Runs the command line `full` (program first) in `cwd` (fork/exec, no shell); with
// signalAfterMs > 0, sends `sig` to it after that many milliseconds; with `signalWhen` not empty,
// as soon as its output contains that text instead (or after signalAfterMs, if it never does):
// how a test interrupts work once it has started, however long the start takes on a driver.
inline RunResult runCommand(std::vector<std::string> full, const fs::path& cwd,
                            int signalAfterMs = 0, int sig = 0,
                            const std::string& signalWhen = "") {
    std::vector<char*> argv;
    for (auto& a : full)
        argv.push_back(a.data());
    argv.push_back(nullptr);

    int fds[2];
    if (::pipe(fds) != 0) return {-1, "pipe() failed"};
    pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return {-1, "fork() failed"};
    }
    if (pid == 0) {
        ::close(fds[0]);
        ::dup2(fds[1], STDOUT_FILENO);
        ::dup2(fds[1], STDERR_FILENO);
        ::close(fds[1]);
        int devnull = ::open("/dev/null", O_RDONLY);
        if (devnull >= 0) ::dup2(devnull, STDIN_FILENO);
        if (::chdir(cwd.c_str()) != 0) ::_exit(126);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    ::close(fds[1]);
    if (signalAfterMs > 0 && signalWhen.empty()) {
        ::usleep(useconds_t(signalAfterMs) * 1000u);
        ::kill(pid, sig);
    }
    RunResult r;
    char buf[4096];
    bool signalled = signalWhen.empty();
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
        if (!signalled) { // wait for output at most until the deadline, in steps of 50 ms
            const double ms =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count();
            if (r.output.find(signalWhen) != std::string::npos || ms > signalAfterMs) {
                ::kill(pid, sig);
                signalled = true;
            } else {
                pollfd p{fds[0], POLLIN, 0};
                if (::poll(&p, 1, 50) == 0) continue;
            }
        }
        ssize_t n = ::read(fds[0], buf, sizeof buf);
        if (n > 0)
            r.output.append(buf, static_cast<size_t>(n));
        else if (n < 0 && errno == EINTR)
            continue;
        else
            break;
    }
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFEXITED(status))
        r.code = WEXITSTATUS(status);
    else if (WIFSIGNALED(status))
        r.code = 128 + WTERMSIG(status);
    // the tests run every command with $BSSRDF_WORKBENCH_GL_BARRIERS set (tests/CMakeLists.txt):
    // a missing memory barrier in the command's GL work fails the test as in-process GL does
    if (const size_t at = r.output.find("barrier missing:"); at != std::string::npos)
        ADD_FAILURE() << r.output.substr(at, r.output.find('\n', at) - at);
    return r;
}

// Runs BW_EXE --root BW_SOURCE_ROOT ARGS... in `cwd`.
inline RunResult runExe(const std::vector<std::string>& args, const fs::path& cwd) {
    std::vector<std::string> full = {BW_EXE, "--root", BW_SOURCE_ROOT};
    full.insert(full.end(), args.begin(), args.end());
    return runCommand(std::move(full), cwd);
}

inline std::string readText(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

inline void writeText(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

} // namespace clitest
