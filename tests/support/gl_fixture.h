// Shared by GL tests: one headless context per test binary, a throwaway project root, helpers.
#pragma once

#include "core/core.h"
#include "gl/gl.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

namespace testsupport {

inline gl::Context& context() {
    static std::unique_ptr<gl::Context> ctx = gl::createHeadlessContext();
    ctx->makeCurrent();
    return *ctx;
}

inline std::filesystem::path sourceRoot() {
    return BW_SOURCE_ROOT;
}

// A fresh project root in /tmp with a copy of shaders/ and materials/ (only the listed models),
// removed when the test process ends (scratch_dir.h).
inline std::filesystem::path makeProjectRoot(const std::string& tag,
                                             const std::vector<std::string>& models) {
    namespace fs = std::filesystem;
    fs::path root = fs::temp_directory_path() / ("bw_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    removeAtExit(root);
    fs::create_directories(root / "materials");
    fs::create_directories(root / "captures");
    fs::copy(sourceRoot() / "shaders", root / "shaders", fs::copy_options::recursive);
    fs::copy_file(sourceRoot() / "materials" / "presets.json", root / "materials" / "presets.json");
    // the default scene's mesh and environment (the scene panels are open by default)
    fs::create_directories(root / "third_party" / "bunny");
    fs::copy_file(sourceRoot() / "third_party" / "bunny" / "bunny.obj",
                  root / "third_party" / "bunny" / "bunny.obj");
    fs::copy(sourceRoot() / "materials" / "env", root / "materials" / "env",
             fs::copy_options::recursive);
    for (const auto& m : models)
        fs::copy_file(sourceRoot() / "materials" / m, root / "materials" / m);
    return root;
}

// A copy of the committed capture captures/<name> as <root>/captures/<as>, with the bunny the
// scene captures read (third_party/bunny/bunny.obj) under `root`. Returns the capture folder.
inline std::filesystem::path copyCapture(const std::filesystem::path& root, const std::string& name,
                                         const std::string& as) {
    namespace fs = std::filesystem;
    const fs::path bunny = "third_party/bunny/bunny.obj";
    if (!fs::exists(root / bunny)) {
        fs::create_directories((root / bunny).parent_path());
        fs::copy_file(sourceRoot() / bunny, root / bunny);
    }
    const fs::path dir = root / "captures" / as;
    fs::create_directories(dir.parent_path());
    fs::copy(sourceRoot() / "captures" / name, dir, fs::copy_options::recursive);
    return dir;
}

inline std::string readText(const std::filesystem::path& p) {
    return core::readFile(p);
}

// Replaces the first occurrence of `from` with `to`; fails the test if absent.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << "missing: " << from;
    if (pos == std::string::npos) return text;
    // concatenation, not std::string::replace: GCC 12 -O3 warns falsely (-Wrestrict) there
    return text.substr(0, pos) + to + text.substr(pos + from.size());
}

// 1-based line of the first line containing `needle`.
inline int lineOf(const std::string& text, const std::string& needle) {
    auto pos = text.find(needle);
    EXPECT_NE(pos, std::string::npos) << needle;
    return core::lineOfOffset(text, pos);
}

} // namespace testsupport
