// Folders a test process makes under the system's temporary directory, removed when the process
// ends (every test runs in its own process under ctest), so that test runs do not pile up copies
// of the project in /tmp. BW_KEEP_TEST_DIRS=1 in the environment keeps them to look at after a
// failure.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace testsupport {

// Removes `dir` (and what it holds) at the end of the process.
inline void removeAtExit(const std::filesystem::path& dir) {
    static std::mutex mutex;
    static std::vector<std::filesystem::path> dirs;
    static const bool registered = [] {
        // registered after `dirs` is made, so it runs before `dirs` is destroyed
        std::atexit([] {
            const char* keep = std::getenv("BW_KEEP_TEST_DIRS");
            if (keep && std::string(keep) == "1") return;
            std::lock_guard lock(mutex);
            for (const auto& d : dirs) {
                std::error_code ec;
                std::filesystem::remove_all(d, ec);
            }
        });
        return true;
    }();
    (void)registered;
    std::lock_guard lock(mutex);
    dirs.push_back(dir);
}

} // namespace testsupport
