// Linked into every `gl` test: a GL debug message of type ERROR or UNDEFINED_BEHAVIOR (what NVIDIA
// reports for, e.g., a depth texture sampled without comparison through a shadow sampler) fails
// the running test, on any driver; so does a missing memory barrier (gl/hazards.cpp checks them
// in every test). The compiler's own messages are left to the tests of shader
// errors. A test that provokes GL errors on purpose holds a bwtest::ExpectedGlErrors.
#include "gl_debug_guard.h"

#include "gl/gl.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <atomic>

namespace bwtest {
namespace {

std::atomic<int> g_expected{0};
std::atomic<long> g_seen{0};

void observe(GLenum source, GLenum type, GLenum, const char* message) {
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER) return;
    if (type != GL_DEBUG_TYPE_ERROR && type != GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR) return;
    if (g_expected.load() > 0) {
        ++g_seen;
        return;
    }
    if (!::testing::UnitTest::GetInstance()->current_test_info()) return; // between tests
    ADD_FAILURE() << "GL debug message of type "
                  << (type == GL_DEBUG_TYPE_ERROR ? "ERROR" : "UNDEFINED_BEHAVIOR") << ": "
                  << message;
}

const bool g_installed = [] {
    gl::setDebugObserver(observe);
    gl::requestBarrierChecks(); // a missing glMemoryBarrier is undefined behaviour too
    return true;
}();

} // namespace

ExpectedGlErrors::ExpectedGlErrors() : m_before(g_seen.load()) {
    ++g_expected;
}
ExpectedGlErrors::~ExpectedGlErrors() {
    --g_expected;
}
long ExpectedGlErrors::count() const {
    return g_seen.load() - m_before;
}

void expectGlProblem(const std::function<void()>& provoke, const std::string& text) {
    ::testing::TestPartResultArray results;
    {
        ::testing::ScopedFakeTestPartResultReporter reporter(
            ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
        provoke();
    }
    bool named = false;
    std::string all;
    for (int i = 0; i < results.size(); ++i) {
        const std::string m = results.GetTestPartResult(i).message();
        all += m + "\n";
        EXPECT_NE(m.find("GL debug message of type"), std::string::npos)
            << "a failure that is not a GL debug message: " << m;
        named = named || m.find(text) != std::string::npos;
    }
    EXPECT_GE(results.size(), 1) << "no GL debug message failed the test";
    EXPECT_TRUE(named) << "no GL debug message said \"" << text << "\"; they said:\n" << all;
}

} // namespace bwtest
