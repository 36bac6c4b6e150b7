// Hot reload under hostile file-system events, with real files, inotify and GL: a burst of 100
// rename-saves (the last version wins), the materials folder deleted and recreated, a model
// replaced by a directory or a symlink loop, a 100 MB file. Nothing crashes, every problem is
// an entry naming the file, and the workbench recovers when the files are good again.
#include "../support/gl_fixture.h"
#include "../support/workbench_values.h"
#include "core/core.h"
#include "pipeline/workbench.h"

#include <fstream>
#include <thread>

using testsupport::replaced;

namespace {
namespace fs = std::filesystem;
using testsupport::valueAt0;

using testsupport::waitFor;

void renameSave(const fs::path& file, const std::string& text) {
    const fs::path tmp = file.parent_path() / ("." + file.filename().string() + ".swp");
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
    }
    fs::rename(tmp, file);
}

bool hasErrorNaming(app::Workbench& wb, const std::string& what) {
    for (const auto& e : wb.errors())
        if (e.text.find(what) != std::string::npos) return true;
    return false;
}

struct Project {
    fs::path root, file;
    std::string path = "materials/dipole.bssrdf", good;
};
Project project(const std::string& tag) {
    testsupport::context();
    Project p;
    p.root = testsupport::makeProjectRoot(tag, {"dipole.bssrdf"});
    p.file = p.root / p.path;
    p.good = testsupport::readText(p.file);
    return p;
}
std::string scaled(const std::string& good, int k) {
    return replaced(good, "return Multiplier/(4.0*PI)",
                    "return " + std::to_string(k) + ".0*Multiplier/(4.0*PI)");
}

} // namespace

TEST(HotReloadHostile, BurstOfRenameSavesTheLastVersionWins) {
    auto p = project("burst");
    app::Workbench wb(p.root, true);
    ASSERT_TRUE(wb.watching());
    const double base = valueAt0(wb, p.path);
    ASSERT_GT(base, 0.0);
    core::Stopwatch sw;
    for (int k = 1; k <= 100; ++k) {
        renameSave(p.file, scaled(p.good, k));
        if (k % 10 == 0) wb.update(); // the UI keeps running during the burst
    }
    const double burstMs = sw.ms();
    EXPECT_TRUE(waitFor(
        wb, [&] { return std::abs(valueAt0(wb, p.path) - 100 * base) < 1e-5 * 100 * base; }))
        << "value " << valueAt0(wb, p.path) << " base " << base << " burst " << burstMs << " ms";
    // and it stays there: no late event brings an older version back
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    wb.update();
    EXPECT_NEAR(valueAt0(wb, p.path), 100 * base, 1e-5 * 100 * base);
    EXPECT_TRUE(wb.errors().empty());
    fs::remove_all(p.root);
}

TEST(HotReloadHostile, MaterialsFolderDeletedAndRecreated) {
    auto p = project("folder");
    app::Workbench wb(p.root, true);
    ASSERT_GT(valueAt0(wb, p.path), 0.0);
    const double base = valueAt0(wb, p.path);
    fs::remove_all(p.root / "materials");
    EXPECT_TRUE(waitFor(wb, [&] { return wb.library().find(p.path) == nullptr; }));
    fs::create_directories(p.root / "materials");
    core::writeFile(p.file, scaled(p.good, 3));
    EXPECT_TRUE(waitFor(wb, [&] {
        return std::abs(valueAt0(wb, p.path) - 3 * base) < 1e-5 * 3 * base;
    })) << "the recreated folder is watched again";
    fs::remove_all(p.root);
}

TEST(HotReloadHostile, ModelReplacedByADirectoryOrASymlinkLoop) {
    auto p = project("dirloop");
    app::Workbench wb(p.root, true);
    const double base = valueAt0(wb, p.path);
    ASSERT_GT(base, 0.0);
    // a directory where the model was
    fs::remove(p.file);
    fs::create_directory(p.file);
    waitFor(
        wb, [&] { return false; }, 300);
    EXPECT_TRUE(wb.library().find(p.path) == nullptr || hasErrorNaming(wb, p.path));
    fs::remove(p.file);
    // a symlink loop: a.bssrdf -> b.bssrdf -> a.bssrdf
    const fs::path a = p.root / "materials/a.bssrdf", b = p.root / "materials/b.bssrdf";
    fs::create_symlink(b, a);
    fs::create_symlink(a, b);
    waitFor(
        wb, [&] { return false; }, 300);
    for (const auto& e : wb.library().entries())
        if (e.displayPath == "materials/a.bssrdf") {
            EXPECT_TRUE(e.problem.has_value());
        }
    fs::remove(a);
    fs::remove(b);
    // good again
    core::writeFile(p.file, scaled(p.good, 2));
    EXPECT_TRUE(
        waitFor(wb, [&] { return std::abs(valueAt0(wb, p.path) - 2 * base) < 1e-5 * 2 * base; }));
    fs::remove_all(p.root);
}

TEST(HotReloadHostile, HundredMegabyteModelIsRefusedNamingTheLimit) {
    auto p = project("huge");
    app::Workbench wb(p.root, true);
    const double base = valueAt0(wb, p.path);
    ASSERT_GT(base, 0.0);
    {
        std::ofstream out(p.file, std::ios::binary | std::ios::trunc);
        out << p.good;
        const std::string comment = "# " + std::string(1022, 'x') + "\n";
        for (int i = 0; i < 100 * 1024; ++i)
            out << comment;
    }
    ASSERT_GE(fs::file_size(p.file), 100u << 20);
    EXPECT_TRUE(waitFor(wb, [&] { return hasErrorNaming(wb, "materials/dipole.bssrdf"); }));
    EXPECT_TRUE(hasErrorNaming(wb, "MiB")) << (wb.errors().empty() ? "" : wb.errors()[0].text);
    EXPECT_NEAR(valueAt0(wb, p.path), base, 1e-6 * base); // the last good version stays
    core::writeFile(p.file, p.good);
    EXPECT_TRUE(waitFor(wb, [&] { return wb.errors().empty(); }));
    fs::remove_all(p.root);
}
