// Hot reload of a model file the workbench may not read, checked for real although the tests run
// as root: the test thread (which runs update() and reads the models) drops CAP_DAC_OVERRIDE and
// CAP_DAC_READ_SEARCH from its effective set for the test. A mode change to 000, and a save of
// a new version without read permission, are Errors entries naming the file; the last good
// version stays; readable again, the new version is adopted.
#include "../support/gl_fixture.h"
#include "../support/workbench_values.h"
#include "core/core.h"
#include "pipeline/workbench.h"

#include <cstdio>
#include <thread>

#include <linux/capability.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

using testsupport::replaced;

namespace {
namespace fs = std::filesystem;
using testsupport::errorNaming;
using testsupport::valueAt0;

using testsupport::waitFor;
} // namespace

namespace {
// Drops CAP_DAC_OVERRIDE and CAP_DAC_READ_SEARCH from the calling thread's effective set (the
// thread that runs update() and reads the models) while it lives, so that a file without read
// permission is unreadable even to root; the permitted set keeps them, so they come back.
class WithoutDacOverride {
  public:
    WithoutDacOverride() {
        if (::syscall(SYS_capget, &m_header, m_saved) != 0) return;
        __user_cap_data_struct dropped[2] = {m_saved[0], m_saved[1]};
        dropped[0].effective &= ~(CAP_TO_MASK(CAP_DAC_OVERRIDE) | CAP_TO_MASK(CAP_DAC_READ_SEARCH));
        m_dropped = ::syscall(SYS_capset, &m_header, dropped) == 0;
    }
    ~WithoutDacOverride() {
        if (m_dropped) ::syscall(SYS_capset, &m_header, m_saved);
    }
    bool dropped() const { return m_dropped; }

  private:
    __user_cap_header_struct m_header{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct m_saved[2] = {};
    bool m_dropped = false;
};
} // namespace

TEST(HotReloadUnreadable, AnErrorNamingTheFileTheLastGoodVersionStays) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("unreadable", {"dipole.bssrdf"});
    const std::string path = "materials/dipole.bssrdf";
    const fs::path file = root / path;
    const std::string good = testsupport::readText(file);
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    WithoutDacOverride guard;
    if (!guard.dropped())
        GTEST_SKIP() << "cannot drop CAP_DAC_OVERRIDE / CAP_DAC_READ_SEARCH (capset refused)";
    ASSERT_EQ(::chmod(file.c_str(), 0), 0);
    if (std::FILE* f = std::fopen(file.c_str(), "rb")) {
        std::fclose(f);
        ::chmod(file.c_str(), 0644);
        GTEST_SKIP() << "a file of mode 000 is still readable without CAP_DAC_OVERRIDE";
    }
    // the mode change (IN_ATTRIB) reads the model again, which fails
    std::string error;
    waitFor(
        wb,
        [&] {
            error = errorNaming(wb, path);
            return !error.empty();
        },
        8000);
    EXPECT_NE(error.find("Permission denied"), std::string::npos) << error;
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    EXPECT_TRUE(wb.library().find(path)->usable());
    // a new version saved without read permission: the same
    {
        const fs::path tmp = root / "materials" / "next.tmp";
        core::writeFile(
            tmp, replaced(good, "return Multiplier/(4.0*PI)", "return 2.0*Multiplier/(4.0*PI)"));
        ASSERT_EQ(::chmod(tmp.c_str(), 0), 0);
        fs::rename(tmp, file);
    }
    waitFor(
        wb, [&] { return false; }, 500);
    EXPECT_NE(errorNaming(wb, path).find("Permission denied"), std::string::npos);
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    // readable again: that version is adopted
    ASSERT_EQ(::chmod(file.c_str(), 0644), 0);
    waitFor(
        wb, [&] { return std::abs(valueAt0(wb, path) - 2 * base) < 1e-5 * base; }, 8000);
    EXPECT_NEAR(valueAt0(wb, path), 2 * base, 1e-5 * base);
    EXPECT_TRUE(errorNaming(wb, path).empty()) << errorNaming(wb, path);
    fs::remove_all(root);
}
