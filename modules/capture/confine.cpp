// Untrusted captures: the files a manifest names stay inside the capture folder, and its input
// paths inside the folders the replay allows (capture.h). Paths are compared after
// std::filesystem::weakly_canonical, which resolves "..", "." and every symlink of the part that
// exists, so neither a "../" nor a symlink planted in the capture folder leads out of it.
#include "capture/capture.h"

#include <system_error>

namespace capture {
namespace fs = std::filesystem;

namespace {

// `path` with symlinks and dot components resolved as far as it exists; empty on error.
fs::path resolved(const fs::path& path) {
    std::error_code ec;
    fs::path r = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return ec ? fs::path() : r;
}

// Whether `path` is `folder` or lies below it (both already resolved).
bool inside(const fs::path& path, const fs::path& folder) {
    if (path.empty() || folder.empty()) return false;
    auto f = folder.begin(), p = path.begin();
    for (; f != folder.end(); ++f, ++p) {
        if (f->empty()) continue; // a trailing separator of the folder
        if (p == path.end() || *p != *f) return false;
    }
    return true;
}

} // namespace

std::string outputPathProblem(const fs::path& captureDir, const std::string& file) {
    if (std::string bad = relativePathProblem(file); !bad.empty()) return bad;
    const fs::path full = captureDir / file;
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(full, ec)))
        return "is a symbolic link; a capture's outputs must be plain files in its folder";
    const fs::path dir = resolved(captureDir), target = resolved(full);
    if (!inside(target, dir) || target == dir)
        return "resolves to " + target.string() + ", outside the capture folder " + dir.string();
    return "";
}

std::string confinedInputProblem(const std::string& path, const fs::path& projectRoot,
                                 const std::vector<fs::path>& folders) {
    if (path.empty()) return "";
    const fs::path p(path);
    const fs::path target = resolved(p.is_absolute() ? p : projectRoot / p);
    for (const fs::path& f : folders)
        if (inside(target, resolved(f))) return "";
    std::string list;
    for (const fs::path& f : folders)
        list += (list.empty() ? "" : ", ") + resolved(f).string();
    return "resolves to " + (target.empty() ? path : target.string()) +
           ", outside the folders a capture may read (" + list + ")";
}

} // namespace capture
