// Replays every committed fuzz input through its target's body (fuzz_NAME.cpp compiled into this
// test with its entry point renamed fuzzOne_NAME): each file of regressions/NAME/ (inputs that
// once crashed, hung or printed raw bytes) and each seed of corpus/NAME/ must end in success or
// in a core::Error with a printable message. Also tests core::printableText.
#include "core/core.h"
#include "fuzz_common.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#define BW_FUZZ_TARGETS(X)                                                                         \
    X(bssrdf_model)                                                                                \
    X(profile_csv)                                                                                 \
    X(bwtable)                                                                                     \
    X(capture_csv) X(manifest) X(obj) X(ply) X(exr) X(presets) X(settings) X(scores) X(mco)

#define BW_DECLARE(name) extern "C" int fuzzOne_##name(const uint8_t* data, size_t size);
BW_FUZZ_TARGETS(BW_DECLARE)
#undef BW_DECLARE

namespace {
namespace fs = std::filesystem;

using Entry = int (*)(const uint8_t*, size_t);

// The targets write their inputs under fuzz::scratchDir(); removed when the tests end.
class RemoveScratch : public ::testing::Environment {
  public:
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(fuzz::scratchDir(), ec);
    }
};
[[maybe_unused]] ::testing::Environment* const kRemoveScratch =
    ::testing::AddGlobalTestEnvironment(new RemoveScratch);

std::vector<fs::path> filesIn(const fs::path& dir) {
    std::vector<fs::path> out;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

void replay(const std::string& name, Entry entry) {
    const fs::path root = fs::path(BW_SOURCE_ROOT) / "tests" / "fuzz";
    const auto seeds = filesIn(root / "corpus" / name);
    EXPECT_FALSE(seeds.empty()) << "no seed corpus for " << name;
    auto files = filesIn(root / "regressions" / name);
    files.insert(files.end(), seeds.begin(), seeds.end());
    for (const fs::path& f : files) {
        SCOPED_TRACE(f.string());
        const std::string bytes = core::readFile(f);
        EXPECT_NO_THROW(entry(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
    }
}

#define BW_TEST(name)                                                                              \
    TEST(FuzzRegressions, name) {                                                                  \
        replay(#name, &fuzzOne_##name);                                                            \
    }
BW_FUZZ_TARGETS(BW_TEST)
#undef BW_TEST

TEST(PrintableText, EscapesControlAndInvalidBytes) {
    EXPECT_EQ(core::printableText("plain, tab\t and\nnewline"), "plain, tab\t and\nnewline");
    EXPECT_EQ(core::printableText("caf\xc3\xa9 \xe2\x86\x92"), "caf\xc3\xa9 \xe2\x86\x92");
    EXPECT_EQ(core::printableText(std::string("a\0b", 3)), "a\\x00b");
    EXPECT_EQ(core::printableText("\x1b[31m\x7f"), "\\x1b[31m\\x7f");
    EXPECT_EQ(core::printableText("\xff\xfe"), "\\xff\\xfe");
    EXPECT_EQ(core::printableText("\xc3"), "\\xc3");          // truncated sequence
    EXPECT_EQ(core::printableText("\xc0\xaf"), "\\xc0\\xaf"); // overlong form
    EXPECT_TRUE(core::isPrintableText("r_mm \xc2\xb5m"));
    EXPECT_FALSE(core::isPrintableText("line\r"));
}

TEST(PrintableText, ErrorMessagesNeverCarryRawBytes) {
    const core::Error e("f\x01.csv", 3, "'\xff\x02' is not a number");
    EXPECT_STREQ(e.what(), "f\\x01.csv:3: '\\xff\\x02' is not a number");
    EXPECT_EQ(e.message(), "'\\xff\\x02' is not a number");
    EXPECT_EQ(e.file(), "f\\x01.csv");
}

} // namespace
