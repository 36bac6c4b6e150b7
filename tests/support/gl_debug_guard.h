// While one of these lives, GL debug errors do not fail the running test (gl_debug_guard.cpp):
// for the tests that provoke them on purpose; count() says how many came.
#pragma once

namespace bwtest {

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
