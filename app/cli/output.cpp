// Output checks of the command line (output.h).
#include "cli/output.h"

#include "core/core.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace app {

void checkWritable(const std::string& path, const std::string& flag) {
    if (path.empty()) return;
    const std::filesystem::path p(path);
    const auto dir = p.parent_path().empty() ? std::filesystem::path(".") : p.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw core::Error(
            flag, 0, "cannot write '" + path + "': folder '" + dir.string() + "' does not exist");
    if (std::filesystem::is_directory(p, ec))
        throw core::Error(flag, 0, "'" + path + "' is a folder");
    // outputs are written to a temporary file and renamed into place: never over a device,
    // FIFO or socket (/dev/full, /dev/null)
    if (std::filesystem::exists(p, ec) && !std::filesystem::is_regular_file(p, ec))
        throw core::Error(flag, 0, "'" + path + "' is not a regular file");
    const bool existed = std::filesystem::exists(p, ec);
    std::ofstream probe(p, std::ios::app);
    if (!probe) throw core::Error(flag, 0, "cannot write '" + path + "'");
    probe.close();
    if (!existed) std::filesystem::remove(p, ec);
}

void checkOutput(const std::string& path, const std::string& flag, const std::string& extension) {
    if (path.empty()) return;
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != extension)
        throw core::Error(flag, 0,
                          "'" + path + "' must end in " + extension + ": the file is written in " +
                              "that format");
    checkWritable(path, flag);
}

std::string pathRate(uint64_t done, double seconds) {
    if (done == 0 || !(seconds >= 0.1)) return "-- paths/s";
    char b[48];
    std::snprintf(b, sizeof b, "%.0f paths/s", double(done) / seconds);
    return b;
}

void printPathProgress(const char* what, uint64_t done, uint64_t total, double seconds) {
    core::progress("%s: %5.1f%%  %llu / %llu paths  %s", what,
                   total ? 100.0 * double(done) / double(total) : 100.0,
                   static_cast<unsigned long long>(done), static_cast<unsigned long long>(total),
                   pathRate(done, seconds).c_str());
}

} // namespace app
