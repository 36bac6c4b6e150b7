// A new model made from an existing one (new_model.h).
#include "pipeline/new_model.h"

#include "capture/capture.h"
#include "core/core.h"

namespace app {
namespace fs = std::filesystem;

namespace {
std::string withoutExtension(std::string name) {
    const std::string ext = ".bssrdf";
    if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
        name.resize(name.size() - ext.size());
    return name;
}
} // namespace

std::string newModelProblem(const fs::path& root, std::string name) {
    name = withoutExtension(std::move(name));
    // the rule of a capture's name: a plain file name on every system
    if (std::string bad = capture::nameProblem(name); !bad.empty()) return bad;
    std::error_code ec;
    if (fs::exists(root / "materials" / (name + ".bssrdf"), ec))
        return "materials/" + name + ".bssrdf exists (a model is never overwritten)";
    return "";
}

fs::path createModel(const fs::path& root, std::string name, const fs::path& from) {
    name = withoutExtension(std::move(name));
    if (std::string bad = newModelProblem(root, name); !bad.empty())
        throw core::Error(name, 0, bad);
    std::error_code ec;
    if (from.extension() != ".bssrdf" || !fs::is_regular_file(from, ec))
        throw core::Error(from.string(), 0, "not a .bssrdf model file to start from");
    const std::string text = core::readFile(from);
    const fs::path file = root / "materials" / (name + ".bssrdf");
    std::string shown = core::relativeTo(fs::absolute(from).lexically_normal(), root);
    const std::string date = capture::utcNow().substr(0, 10);
    core::writeFile(file, "# " + name + ": made from " + shown + " on " + date +
                              "; edit it and save, the workbench reloads it\n" + text);
    return file;
}

} // namespace app
