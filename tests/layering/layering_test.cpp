// Module layering: every module may use only the modules below it, by #include and by
// target_link_libraries. The allowed graph is the table below (core ← gl ← shader ← bssrdf ←
// render, …; app, on top, may use all). A module missing from the table, an include or link of
// a module it may not use, or a cycle in the table fails; the synthetic trees show each check
// failing on a violation.
#include "layering_support.h"

#include "core/core.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {
using namespace layering;

// Allowed direct dependencies of each module (modules/<m>/). Add a new module here, below
// everything it uses.
const Graph kAllowed = {
    {"core", {}},
    {"litsphere", {}},
    {"gl", {"core"}},
    {"shader", {"core", "gl"}},
    {"material", {"core"}},
    {"mesh", {"core"}},
    {"plot", {"core"}},
    {"capture", {"core"}},
    {"octree", {"core"}},
    {"pointcloud", {"core", "mesh"}},
    {"bssrdf", {"core", "gl", "shader", "litsphere", "pathtrace"}},
    {"pathtrace", {"core", "gl", "shader", "litsphere", "mesh"}},
    {"sampling", {"core", "mesh"}},
    {"irradiance", {"core", "gl", "shader", "mesh", "pointcloud"}},
    {"render", {"core", "gl", "shader", "bssrdf", "octree", "mesh", "pathtrace"}},
    {"integrate", {"core", "gl", "litsphere", "mesh", "bssrdf", "sampling", "render", "pathtrace"}},
    {"texspace",
     {"core", "mesh", "gl", "shader", "irradiance", "octree", "render", "litsphere", "bssrdf"}},
};

// "modules/a/x.cpp:3: includes b/y.h" for each use of a module `a` may not use.
std::vector<std::string> violations(const fs::path& modulesDir, const Graph& allowed) {
    std::set<std::string> modules;
    for (const auto& d : fs::directory_iterator(modulesDir))
        if (d.is_directory()) modules.insert(d.path().filename().string());
    std::vector<std::string> out;
    const std::regex include(R"(^\s*#\s*include\s*[<"]([A-Za-z0-9_]+)/)");
    const std::regex link(R"(\bbw_([A-Za-z0-9_]+)\b)");
    for (const auto& m : modules) {
        auto it = allowed.find(m);
        if (it == allowed.end()) {
            out.push_back("modules/" + m + ": not in the layering table");
            continue;
        }
        auto check = [&](const std::string& used, const fs::path& file, int line,
                         const std::string& how) {
            if (used == m || !modules.count(used) || it->second.count(used)) return;
            out.push_back(core::relativeTo(file, modulesDir.parent_path()) + ":" +
                          std::to_string(line) + ": " + m + " " + how + " " + used);
        };
        for (const auto& f : fs::recursive_directory_iterator(modulesDir / m)) {
            if (!f.is_regular_file()) continue;
            const std::string name = f.path().filename().string();
            const std::string ext = f.path().extension().string();
            const bool cmake = name == "CMakeLists.txt";
            if (!cmake && ext != ".h" && ext != ".cpp") continue;
            std::istringstream in(readAll(f.path()));
            std::string text;
            int lineNo = 0;
            while (std::getline(in, text)) {
                ++lineNo;
                std::smatch match;
                if (cmake) {
                    if (text.find('#') != std::string::npos) text = text.substr(0, text.find('#'));
                    for (std::sregex_iterator i(text.begin(), text.end(), link), e; i != e; ++i)
                        check((*i)[1].str(), f.path(), lineNo, "links");
                } else if (std::regex_search(text, match, include)) {
                    check(match[1].str(), f.path(), lineNo, "includes");
                }
            }
        }
    }
    return out;
}

} // namespace

TEST(Layering, NoModuleUsesAModuleAboveIt) {
    ASSERT_TRUE(acyclic(kAllowed));
    const auto v = violations(fs::path(BW_SOURCE_ROOT) / "modules", kAllowed);
    std::string all;
    for (const auto& s : v)
        all += s + "\n";
    EXPECT_TRUE(v.empty()) << all;
}

TEST(Layering, AnUpwardIncludeOrLinkIsReported) {
    TempTree t;
    t.write("modules/gl/gl.h", "#pragma once\n");
    t.write("modules/shader/program.h", "#pragma once\n#include \"gl/gl.h\"\n");
    t.write("modules/bssrdf/program.h", "#pragma once\n#include \"shader/program.h\"\n");
    t.write("modules/shader/CMakeLists.txt", "target_link_libraries(bw_shader PUBLIC bw_gl)\n");
    const Graph g = {{"gl", {}}, {"shader", {"gl"}}, {"bssrdf", {"shader"}}};
    EXPECT_TRUE(violations(t.root / "modules", g).empty());

    // shader reaching up into bssrdf, by #include and by link
    t.write("modules/shader/assembly.cpp",
            "// x\n#include <vector>\n #include \"bssrdf/program.h\"\n");
    t.write("modules/shader/CMakeLists.txt",
            "# bw_bssrdf in a comment is fine\ntarget_link_libraries(bw_shader PUBLIC bw_gl "
            "bw_bssrdf)\n");
    const auto v = violations(t.root / "modules", g);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_NE(
        std::find(v.begin(), v.end(), "modules/shader/assembly.cpp:3: shader includes bssrdf"),
        v.end());
    EXPECT_NE(std::find(v.begin(), v.end(), "modules/shader/CMakeLists.txt:2: shader links bssrdf"),
              v.end());

    // a module nobody placed in the table
    t.write("modules/newstage/x.h", "#pragma once\n");
    EXPECT_EQ(violations(t.root / "modules", g).size(), 3u);

    // an upward arrow in the table itself is a cycle
    EXPECT_FALSE(acyclic({{"gl", {"shader"}}, {"shader", {"gl"}}}));
}
