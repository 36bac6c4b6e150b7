// A capture replayed by a child process (`bssrdf-workbench --root ROOT replay DIR`) whose
// output the GUI reads without blocking: the replay needs its own GL context and may take
// seconds, and a child can neither freeze nor crash the workbench, and can be cancelled.
#pragma once

#include <filesystem>
#include <string>

#include <sys/types.h>

namespace app {

class ReplayProcess {
  public:
    // Starts the replay; throws core::Error when the process cannot be started.
    ReplayProcess(const std::filesystem::path& exe, const std::filesystem::path& root,
                  const std::filesystem::path& captureDir);
    ~ReplayProcess(); // kills a replay still running
    ReplayProcess(const ReplayProcess&) = delete;
    ReplayProcess& operator=(const ReplayProcess&) = delete;

    // Reads what the child wrote so far; true once it has exited (then exitCode() is valid).
    bool poll();
    void cancel();
    const std::string& output() const { return m_output; }
    int exitCode() const { return m_code; } // 128 + signal when killed
    bool done() const { return m_done; }

  private:
    pid_t m_pid = -1;
    int m_fd = -1;
    std::string m_output;
    int m_code = -1;
    bool m_done = false;
};

// The executable of this process (/proc/self/exe).
std::filesystem::path selfExecutable();

} // namespace app
