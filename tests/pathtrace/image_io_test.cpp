// pathtrace image_io: EXR round trip is bitwise exact (means, variances, sample count,
// non-square, infinities), unwritable and unreadable paths give errors naming them.
#include "../support/scratch_dir.h"
#include "core/core.h"
#include "pathtrace/image_io.h"
#include "pathtrace/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <unistd.h>

using namespace pathtrace;
namespace fs = std::filesystem;

namespace {
fs::path tempPath(const std::string& name) {
    const fs::path p =
        fs::temp_directory_path() / ("bw_exr_test_" + std::to_string(::getpid()) + "_" + name);
    testsupport::removeAtExit(p);
    return p;
}
void expectErrorNaming(const std::function<void()>& f, const std::string& path) {
    try {
        f();
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), path);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}
} // namespace

TEST(ImageIo, RoundTripIsBitwiseExact) {
    Image img;
    img.width = 37;
    img.height = 19;
    img.samples = 123456789012ull;
    const size_t n = 3u * 37 * 19;
    Pcg32 rng(1, 2);
    for (size_t i = 0; i < n; ++i) {
        img.mean.push_back(
            static_cast<float>(std::ldexp(rng.uniform(), int(rng.nextU32() % 40) - 20)));
        img.variance.push_back(rng.uniformFloat() * 1e-6f);
    }
    img.mean[5] = 0.0f;
    img.variance[7] = std::numeric_limits<float>::infinity();
    img.mean[8] = std::numeric_limits<float>::denorm_min();
    const fs::path p = tempPath("round.exr");
    writeExr(p, img);
    const Image back = readExr(p);
    fs::remove(p);
    EXPECT_EQ(back.width, img.width);
    EXPECT_EQ(back.height, img.height);
    EXPECT_EQ(back.samples, img.samples);
    ASSERT_EQ(back.mean.size(), n);
    ASSERT_EQ(back.variance.size(), n);
    EXPECT_EQ(std::memcmp(back.mean.data(), img.mean.data(), n * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(back.variance.data(), img.variance.data(), n * sizeof(float)), 0);
}

TEST(ImageIo, ErrorsNameThePath) {
    Image img;
    img.width = img.height = 2;
    img.mean.assign(12, 1.0f);
    img.variance.assign(12, 0.0f);
    const std::string bad = "/nonexistent_bw_dir/sub/out.exr";
    expectErrorNaming([&] { writeExr(bad, img); }, bad);
    const fs::path missing = tempPath("missing.exr");
    expectErrorNaming([&] { readExr(missing); }, missing.string());
    const fs::path garbage = tempPath("garbage.exr");
    core::writeFile(garbage, "this is not an EXR file");
    expectErrorNaming([&] { readExr(garbage); }, garbage.string());
    fs::remove(garbage);
    Image broken = img;
    broken.mean.pop_back();
    const fs::path out = tempPath("broken.exr");
    expectErrorNaming([&] { writeExr(out, broken); }, out.string());
    EXPECT_FALSE(fs::exists(out));
}
