// An X server for a test and what a test needs to use a program's window through it, as a user
// would (tests/app/gui_window_test.cpp): Xvfb on the first free display, a child process with
// its output in a file, the window found by its title, its pixels (XGetImage), a PNG read back
// to compare with, and pixel counts over a region.
#pragma once

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <stb_image.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace xtest {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

inline std::string readText(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// A process of our own with its output in a file: fork/exec with extra environment variables.
class Process {
  public:
    Process(std::vector<std::string> argv, const std::vector<std::string>& env,
            const fs::path& output, int keepFd = -1)
        : m_output(output) {
        std::vector<char*> args;
        for (auto& a : argv)
            args.push_back(a.data());
        args.push_back(nullptr);
        m_pid = ::fork();
        if (m_pid == 0) {
            const int out = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (out < 0) ::_exit(126);
            ::dup2(out, STDOUT_FILENO);
            ::dup2(out, STDERR_FILENO);
            const int devnull = ::open("/dev/null", O_RDONLY);
            if (devnull >= 0) ::dup2(devnull, STDIN_FILENO);
            for (int fd = 3; fd < 1024; ++fd)
                if (fd != keepFd) ::close(fd);
            for (const std::string& e : env) {
                const size_t eq = e.find('=');
                ::setenv(e.substr(0, eq).c_str(), e.substr(eq + 1).c_str(), 1);
            }
            ::unsetenv("WAYLAND_DISPLAY");
            ::execvp(args[0], args.data());
            std::fprintf(stderr, "cannot start %s\n", args[0]);
            ::_exit(127);
        }
    }
    ~Process() {
        if (m_pid > 0 && !m_exited) {
            ::kill(m_pid, SIGKILL);
            ::waitpid(m_pid, nullptr, 0);
        }
    }
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    std::string output() const { return readText(m_output); }
    pid_t pid() const { return m_pid; }
    bool running() {
        poll(0);
        return !m_exited;
    }
    // The exit status (128 + signal if killed by one) once the process ended within `seconds`;
    // -1 while it still runs.
    int wait(double seconds) {
        const auto start = Clock::now();
        while (!poll(0) && secondsSince(start) < seconds)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        return m_exited ? m_code : -1;
    }
    // Whether `text` appears in the output (at or after byte `from`) within `seconds`.
    bool waitForOutput(const std::string& text, double seconds, size_t from = 0) {
        const auto start = Clock::now();
        const auto found = [&] {
            const std::string out = output();
            return out.size() > from && out.find(text, from) != std::string::npos;
        };
        while (secondsSince(start) < seconds) {
            if (found()) return true;
            if (!running()) return found();
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return false;
    }

  private:
    bool poll(int options) {
        if (m_exited || m_pid <= 0) return m_exited;
        int status = 0;
        if (::waitpid(m_pid, &status, WNOHANG | options) == m_pid) {
            m_exited = true;
            m_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        return m_exited;
    }
    fs::path m_output;
    pid_t m_pid = -1;
    bool m_exited = false;
    int m_code = -1;
};

// An X server for one test: Xvfb on the first free display (-displayfd), one screen.
class XServer {
  public:
    XServer(const fs::path& dir, int width, int height) {
        int fds[2];
        if (::pipe(fds) != 0) return;
        const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
        m_server = std::make_unique<Process>(
            std::vector<std::string>{"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0",
                                     screen, "-nolisten", "tcp", "-noreset"},
            std::vector<std::string>{}, dir / "xvfb.log", fds[1]);
        ::close(fds[1]);
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        char c = 0;
        while (::poll(&p, 1, 20000) > 0 && ::read(fds[0], &c, 1) == 1 && c != '\n')
            number += c;
        ::close(fds[0]);
        if (number.empty()) {
            m_problem =
                "Xvfb did not start (install xvfb; ./run does): " + readText(dir / "xvfb.log");
            return;
        }
        m_name = ":" + number;
        m_display = XOpenDisplay(m_name.c_str());
        if (!m_display) m_problem = "cannot connect to Xvfb at " + m_name;
    }
    ~XServer() {
        if (m_display) XCloseDisplay(m_display);
        if (m_server && m_server->running()) {
            ::kill(m_server->pid(), SIGTERM);
            m_server->wait(5);
        }
    }
    const std::string& problem() const { return m_problem; }
    const std::string& name() const { return m_name; }
    Display* display() const { return m_display; }

  private:
    std::unique_ptr<Process> m_server;
    std::string m_name, m_problem;
    Display* m_display = nullptr;
};

struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgba;
    const unsigned char* at(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};

// The workbench's top-level window (found by its title), or 0 when it is not mapped yet.
inline Window findWindow(Display* d, const std::string& title) {
    Window root = DefaultRootWindow(d), parent = 0, *children = nullptr;
    unsigned count = 0;
    Window found = 0;
    if (!XQueryTree(d, root, &root, &parent, &children, &count)) return 0;
    for (unsigned i = 0; i < count && !found; ++i) {
        char* name = nullptr;
        XWindowAttributes a{};
        if (XFetchName(d, children[i], &name) && name) {
            if (title == name && XGetWindowAttributes(d, children[i], &a) &&
                a.map_state == IsViewable)
                found = children[i];
            XFree(name);
        }
    }
    if (children) XFree(children);
    return found;
}

inline Image grab(Display* d, Window w) {
    XWindowAttributes a{};
    XGetWindowAttributes(d, w, &a);
    Image img;
    XImage* x = XGetImage(d, w, 0, 0, unsigned(a.width), unsigned(a.height), AllPlanes, ZPixmap);
    if (!x) return img;
    img.width = a.width;
    img.height = a.height;
    img.rgba.resize(size_t(a.width) * a.height * 4);
    for (int y = 0; y < a.height; ++y)
        for (int xx = 0; xx < a.width; ++xx) {
            const unsigned long p = XGetPixel(x, xx, y);
            unsigned char* o = &img.rgba[(size_t(y) * a.width + xx) * 4];
            o[0] = (p & x->red_mask) >> 16;
            o[1] = (p & x->green_mask) >> 8;
            o[2] = p & x->blue_mask;
            o[3] = 255;
        }
    XDestroyImage(x);
    return img;
}

inline Image readPng(const fs::path& file) {
    Image img;
    int n = 0;
    unsigned char* px = stbi_load(file.c_str(), &img.width, &img.height, &n, 4);
    if (!px) return {};
    img.rgba.assign(px, px + size_t(img.width) * img.height * 4);
    stbi_image_free(px);
    return img;
}

inline size_t distinctColours(const Image& img, int x0, int y0, int x1, int y1) {
    std::set<uint32_t> colours;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const unsigned char* p = img.at(x, y);
            colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
        }
    return colours.size();
}

inline size_t pixelsThatDiffer(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
    size_t n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            n += std::memcmp(a.at(x, y), b.at(x, y), 3) != 0;
    return n;
}

} // namespace xtest
