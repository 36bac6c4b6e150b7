// The fixture of the command-line tests: the real executable run in a fresh temporary folder,
// and a rejected input checked for a non-zero exit without a crash and a message containing
// every given fragment.
#pragma once

#include "cli_runner.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace clitest {

class CliFixture : public ::testing::Test {
  protected:
    RunResult run(const std::vector<std::string>& args) { return runExe(args, m_dir.path()); }
    void expectFailure(const std::vector<std::string>& args,
                       const std::vector<std::string>& fragments) {
        RunResult r = run(args);
        EXPECT_NE(r.code, 0) << describe(args, r);
        EXPECT_LT(r.code, 128) << "crashed\n" << describe(args, r);
        for (const auto& f : fragments)
            EXPECT_NE(r.output.find(f), std::string::npos)
                << "expected the message to contain '" << f << "'\n"
                << describe(args, r);
    }
    const std::filesystem::path& dir() const { return m_dir.path(); }

    TempDir m_dir;
};

} // namespace clitest
