// app/ layering: each folder of app/ is a library that may use only the folders below it, by
// #include and by target_link_libraries, as modules/ are checked in layering_test.cpp:
//   common ← probe ← pipeline ← captures ← gui ← bench ← cli ← main.cpp
// Every include of an app header names its folder ("pipeline/workbench.h"), so each arrow is
// checked. ImGui (and the plot widgets drawn with it), GLFW and CLI11 are used only where the
// table of external libraries allows. No two files of app/ include each other, directly or
// through others (a header and its source counted as one file), and no file of app/ is longer
// than kMaxLines. The synthetic trees show each check failing on a violation.
#include "layering_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <sstream>
#include <vector>

namespace {
using namespace layering;

// The folders of app/ and the folders each may use. Add a new folder here, below everything
// it uses; app/main.cpp is above them all.
const Graph kAppAllowed = {
    {"common", {}},
    {"probe", {"common"}},
    {"pipeline", {"common", "probe"}},
    {"captures", {"common", "probe", "pipeline"}},
    {"gui", {"common", "probe", "pipeline", "captures"}},
    {"bench", {"common", "probe", "pipeline", "captures", "gui"}},
    {"cli", {"common", "probe", "pipeline", "captures", "gui", "bench"}},
};

// Libraries only some folders may use: how an include of it starts, its link names.
struct External {
    std::string name;
    std::vector<std::string> includes; // prefixes of the included path
    std::set<std::string> links;       // target_link_libraries names
    std::set<std::string> folders;     // the folders that may use it
};
const std::vector<External> kExternal = {
    {"ImGui",
     {"imgui", "backends/imgui", "plot/plot_draw.h"},
     {"PkgConfig::IMGUI", "bw_plot_draw"},
     {"gui", "bench", "cli"}},
    {"GLFW", {"GLFW/"}, {"glfw"}, {"gui", "bench", "cli"}},
    {"CLI11", {"CLI/"}, {"CLI11::CLI11"}, {"cli"}},
};

// A file longer than this does several jobs: split it by job.
constexpr int kMaxLines = 600;

bool isSource(const fs::path& p) {
    return p.extension() == ".h" || p.extension() == ".cpp";
}

// "app/pipeline/x.cpp:3: pipeline includes gui" for every forbidden use; also folders missing
// from the table, includes of app headers without their folder, and include loops.
std::vector<std::string> appViolations(const fs::path& appDir, const Graph& allowed,
                                       const std::vector<External>& external) {
    std::set<std::string> folders;
    for (const auto& d : fs::directory_iterator(appDir))
        if (d.is_directory()) folders.insert(d.path().filename().string());
    std::vector<std::string> out;
    for (const auto& f : folders)
        if (!allowed.count(f)) out.push_back("app/" + f + ": not in the layering table");

    const std::regex include(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
    // file graph: app-relative path without extension → the ones it includes
    Graph files;
    for (const auto& entry : fs::recursive_directory_iterator(appDir)) {
        if (!entry.is_regular_file()) continue;
        const fs::path rel = fs::relative(entry.path(), appDir);
        const std::string name = rel.filename().string();
        const bool cmake = name == "CMakeLists.txt";
        if (!cmake && !isSource(rel)) continue;
        const std::string folder = rel.has_parent_path() ? rel.begin()->string() : "";
        const std::string where = "app/" + rel.generic_string();
        auto mayUse = [&](const std::string& used) {
            if (folder.empty() || used == folder) return true; // main.cpp, app/CMakeLists.txt
            auto it = allowed.find(folder);
            return it != allowed.end() && it->second.count(used) > 0;
        };
        auto mayUseExternal = [&](const External& e) {
            return folder.empty() || e.folders.count(folder) > 0;
        };
        std::string node = rel.generic_string();
        node = node.substr(0, node.size() - rel.extension().string().size());
        std::istringstream in(readAll(entry.path()));
        std::string text;
        int lineNo = 0;
        while (std::getline(in, text)) {
            ++lineNo;
            const std::string at = where + ":" + std::to_string(lineNo) + ": ";
            if (cmake) {
                if (text.find('#') != std::string::npos) text = text.substr(0, text.find('#'));
                std::replace(text.begin(), text.end(), '(', ' ');
                std::replace(text.begin(), text.end(), ')', ' ');
                std::istringstream words(text);
                for (std::string w; words >> w;) {
                    if (w.rfind("bw_app_", 0) == 0 && folders.count(w.substr(7)) &&
                        !mayUse(w.substr(7)))
                        out.push_back(at + folder + " links " + w.substr(7));
                    for (const auto& e : external)
                        if (e.links.count(w) && !mayUseExternal(e))
                            out.push_back(at + folder + " links " + e.name);
                }
                continue;
            }
            std::smatch m;
            if (!std::regex_search(text, m, include)) continue;
            const std::string path = m[2].str();
            for (const auto& e : external)
                for (const auto& prefix : e.includes)
                    if (path.rfind(prefix, 0) == 0 && !mayUseExternal(e))
                        out.push_back(at + folder + " includes " + e.name);
            if (m[1].str() != "\"") continue;
            const size_t slash = path.find('/');
            const std::string first = slash == std::string::npos ? "" : path.substr(0, slash);
            if (slash == std::string::npos || path.rfind("../", 0) == 0 ||
                path.rfind("./", 0) == 0) {
                out.push_back(at + "includes \"" + path + "\" without its folder");
                continue;
            }
            if (!folders.count(first)) continue; // a module's header
            if (!mayUse(first)) out.push_back(at + folder + " includes " + first);
            std::string target =
                path.substr(0, path.size() - fs::path(path).extension().string().size());
            if (target != node) files[node].insert(target);
        }
    }
    // one loop, as a → b → … → a, when the file graph has one
    std::map<std::string, int> state;
    std::vector<std::string> stack;
    std::function<bool(const std::string&)> visit = [&](const std::string& n) {
        if (state[n] == 1) {
            std::string loop;
            for (auto it = std::find(stack.begin(), stack.end(), n); it != stack.end(); ++it)
                loop += *it + " → ";
            out.push_back("include loop: " + loop + n);
            return false;
        }
        if (state[n] == 2) return true;
        state[n] = 1;
        stack.push_back(n);
        for (const auto& d : files[n])
            if (!visit(d)) return false;
        stack.pop_back();
        state[n] = 2;
        return true;
    };
    for (const auto& [n, deps] : Graph(files))
        if (!visit(n)) break;
    return out;
}

// "app/x.cpp: 612 lines" for every source of app/ over `maxLines`.
std::vector<std::string> longFiles(const fs::path& appDir, int maxLines) {
    std::vector<std::string> out;
    for (const auto& entry : fs::recursive_directory_iterator(appDir)) {
        if (!entry.is_regular_file() || !isSource(entry.path())) continue;
        const std::string text = readAll(entry.path());
        const auto lines = std::count(text.begin(), text.end(), '\n');
        if (lines > maxLines)
            out.push_back("app/" + fs::relative(entry.path(), appDir).generic_string() + ": " +
                          std::to_string(lines) + " lines");
    }
    return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

std::string joined(const std::vector<std::string>& v) {
    std::string all;
    for (const auto& s : v)
        all += s + "\n";
    return all;
}

} // namespace

TEST(AppLayering, NoFolderUsesAFolderAboveItAndNoFilesIncludeEachOther) {
    ASSERT_TRUE(acyclic(kAppAllowed));
    const auto v = appViolations(fs::path(BW_SOURCE_ROOT) / "app", kAppAllowed, kExternal);
    EXPECT_TRUE(v.empty()) << joined(v);
}

TEST(AppLayering, NoFileIsLongerThanItsLimit) {
    const auto v = longFiles(fs::path(BW_SOURCE_ROOT) / "app", kMaxLines);
    EXPECT_TRUE(v.empty()) << joined(v);

    TempTree t;
    std::string text;
    for (int i = 0; i < 12; ++i)
        text += "// line\n";
    t.write("app/pipeline/short.cpp", text.substr(0, 10 * 8));
    t.write("app/pipeline/long.cpp", text);
    EXPECT_EQ(longFiles(t.root / "app", 10),
              std::vector<std::string>{"app/pipeline/long.cpp: 12 lines"});
}

TEST(AppLayering, ABackArrowALibraryOutOfPlaceAndALoopAreReported) {
    TempTree t;
    const fs::path app = t.root / "app";
    t.write("app/pipeline/workbench.h", "#pragma once\n#include \"bssrdf/program.h\"\n");
    t.write("app/pipeline/workbench.cpp", "#include \"pipeline/workbench.h\"\n#include <vector>\n");
    t.write("app/gui/gui.cpp",
            "#include \"gui/gui.h\"\n#include \"pipeline/workbench.h\"\n#include <imgui.h>\n");
    t.write("app/gui/gui.h", "#pragma once\n#include <GLFW/glfw3.h>\n");
    t.write("app/gui/CMakeLists.txt",
            "add_library(bw_app_gui STATIC gui.cpp)\n"
            "target_link_libraries(bw_app_gui PUBLIC bw_app_pipeline PkgConfig::IMGUI glfw)\n");
    t.write("app/pipeline/CMakeLists.txt",
            "# bw_app_gui in a comment is fine\n"
            "target_link_libraries(bw_app_pipeline PUBLIC bw_core)\n");
    const Graph g = {{"pipeline", {}}, {"gui", {"pipeline"}}};
    const std::vector<External> ext = {
        {"ImGui", {"imgui"}, {"PkgConfig::IMGUI"}, {"gui"}},
        {"GLFW", {"GLFW/"}, {"glfw"}, {"gui"}},
    };
    EXPECT_TRUE(appViolations(app, g, ext).empty()) << joined(appViolations(app, g, ext));

    // the pipeline reaching up into the GUI, by #include and by link, and using ImGui
    t.write("app/pipeline/scene.cpp", "// x\n#include \"gui/gui.h\"\n#include <imgui.h>\n");
    t.write("app/pipeline/CMakeLists.txt",
            "target_link_libraries(bw_app_pipeline PUBLIC bw_core bw_app_gui glfw)\n");
    auto v = appViolations(app, g, ext);
    EXPECT_EQ(v.size(), 4u) << joined(v);
    EXPECT_TRUE(contains(v, "app/pipeline/scene.cpp:2: pipeline includes gui")) << joined(v);
    EXPECT_TRUE(contains(v, "app/pipeline/scene.cpp:3: pipeline includes ImGui")) << joined(v);
    EXPECT_TRUE(contains(v, "app/pipeline/CMakeLists.txt:1: pipeline links gui")) << joined(v);
    EXPECT_TRUE(contains(v, "app/pipeline/CMakeLists.txt:1: pipeline links GLFW")) << joined(v);
    fs::remove(app / "pipeline/scene.cpp");
    t.write("app/pipeline/CMakeLists.txt",
            "target_link_libraries(bw_app_pipeline PUBLIC bw_core)\n");

    // an include without its folder, a folder nobody placed, and two files including each other
    t.write("app/gui/panel.cpp", "#include \"gui.h\"\n");
    t.write("app/newfolder/x.h", "#pragma once\n");
    t.write("app/pipeline/stage.h", "#pragma once\n#include \"pipeline/workbench.h\"\n");
    t.write("app/pipeline/workbench.cpp", "#include \"pipeline/workbench.h\"\n"
                                          "#include \"pipeline/stage.h\"\n");
    t.write("app/pipeline/workbench.h", "#pragma once\n#include \"pipeline/stage.h\"\n");
    v = appViolations(app, g, ext);
    EXPECT_EQ(v.size(), 3u) << joined(v);
    EXPECT_TRUE(contains(v, "app/gui/panel.cpp:1: includes \"gui.h\" without its folder"))
        << joined(v);
    EXPECT_TRUE(contains(v, "app/newfolder: not in the layering table")) << joined(v);
    const bool loop = std::any_of(v.begin(), v.end(), [](const std::string& s) {
        return s.rfind("include loop: ", 0) == 0 && s.find("pipeline/stage") != s.npos &&
               s.find("pipeline/workbench") != s.npos;
    });
    EXPECT_TRUE(loop) << joined(v);
}
