// A child process of the workbench whose output the GUI reads without blocking: the Captures
// panel's replay (`bssrdf-workbench --root ROOT replay DIR`), recording and windows on captures
// (`gui --capture NAME`), and the check of a new model (model_probe_process.h). Each needs its
// own GL context and may take seconds or never end; a child can neither freeze nor crash the
// workbench, and can be killed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <sys/types.h>

namespace app {

class ChildProcess {
  public:
    // Starts args[0] with args; stdout and stderr go to one pipe; with `input`, its stdin is a
    // socket that send() writes to (else it inherits this process's). Throws core::Error(what,
    // 0, …) when the process cannot be started.
    ChildProcess(const std::vector<std::string>& args, const std::string& what, bool input = false);
    ~ChildProcess(); // kills a child still running
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    // Reads what the child wrote so far; true once it has exited (then exitCode() is valid).
    bool poll();
    void cancel();
    // Writes `bytes` to the child's stdin (a child made with `input`); false when it cannot
    // (the child has closed it or ended). Never raises SIGPIPE.
    bool send(const std::string& bytes);
    // Ends the child's stdin (it reads end of file).
    void closeInput();
    const std::string& output() const { return m_output; }
    int exitCode() const { return m_code; } // 128 + signal when killed
    bool done() const { return m_done; }
    pid_t pid() const { return m_pid; }

  private:
    pid_t m_pid = -1;
    int m_fd = -1;
    int m_in = -1; // our end of the child's stdin, with `input`
    std::string m_output;
    int m_code = -1;
    bool m_done = false;
};

// A capture replayed by a child process (`bssrdf-workbench --root ROOT replay DIR`).
class ReplayProcess : public ChildProcess {
  public:
    ReplayProcess(const std::filesystem::path& exe, const std::filesystem::path& root,
                  const std::filesystem::path& captureDir)
        : ChildProcess({exe.string(), "--root", root.string(), "replay", captureDir.string()},
                       captureDir.string()) {}
};

// The executable of this process (/proc/self/exe).
std::filesystem::path selfExecutable();

} // namespace app
