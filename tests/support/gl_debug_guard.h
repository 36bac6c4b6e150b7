// While one of these lives, GL debug errors do not fail the running test (gl_debug_guard.cpp):
// for the tests that provoke them on purpose; count() says how many came.
#pragma once

#include <functional>
#include <string>

namespace bwtest {

// Runs `provoke` and expects the guard to fail the test for it: at least one failure, every one
// of them a GL debug message, one containing `text`; the failures are swallowed. Drivers differ
// in how many messages one bad call gets (NVIDIA: two for glUseProgram of a name never made; its
// own report beside ours for a shadow sampler without comparison), which EXPECT_NONFATAL_FAILURE
// (exactly one) cannot take.
void expectGlProblem(const std::function<void()>& provoke, const std::string& text);

class ExpectedGlErrors {
  public:
    ExpectedGlErrors();
    ~ExpectedGlErrors();
    ExpectedGlErrors(const ExpectedGlErrors&) = delete;
    ExpectedGlErrors& operator=(const ExpectedGlErrors&) = delete;
    long count() const;

  private:
    long m_before;
};

} // namespace bwtest
