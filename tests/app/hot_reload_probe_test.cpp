// A model whose Bssrdf() does not end, or runs for very long, saved while the workbench runs:
// its first evaluation runs in a child process (the workbench executable,
// app/probe/model_probe_process.h) with a short limit, update() keeps returning at once while it
// runs, the Errors panel names the file and why, the last good version stays in use, and the fixed
// file is adopted.
#include "../support/gl_fixture.h"
#include "../support/small_scene.h"
#include "../support/workbench_values.h"
#include "cli/probe_commands.h"
#include "core/core.h"
#include "pipeline/workbench.h"
#include "probe/child_process.h"
#include "probe/model_probe_process.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <thread>

using testsupport::replaced;

namespace {
namespace fs = std::filesystem;
using testsupport::errorNaming;
using testsupport::valueAt0;

// Runs update() until done() or `ms` pass; returns how many update() calls ended with a check
// under way. An update() that waited for a check would end with none: counting them, not timing
// them, says that the main process never waited, on however loaded a machine.
template <class F> int updateUntil(app::Workbench& wb, F done, double ms = 60000) {
    core::Stopwatch sw;
    int whileChecking = 0;
    while (sw.ms() < ms) {
        wb.update();
        whileChecking += wb.library().checking();
        if (done()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return whileChecking;
}

// The 1-based line of the first `while (` of a model's text.
int whileLine(const std::string& text) {
    const size_t at = text.find("while (");
    return at == std::string::npos
               ? 0
               : 1 + int(std::count(text.begin(), text.begin() + long(at), '\n'));
}

// The dipole with `body` run before its return statement.
std::string withLoop(const std::string& good, const std::string& body) {
    return replaced(good, "return Multiplier/(4.0*PI)", body + "\n    return Multiplier/(4.0*PI)");
}
// The dipole returning `factor` times its value. looped: through a one-iteration loop, so the
// save is checked in the child; a loop-free edit is not, once a check passed in its frame
// (bssrdf::probeFrameKey).
std::string scaled(const std::string& good, double factor, bool looped = true) {
    const std::string f = std::to_string(factor);
    return replaced(good, "return Multiplier/(4.0*PI)",
                    looped ? "float f = 0.0;\n    for (int k = 0; k < 1; ++k) f += " + f +
                                 ";\n    return f*Multiplier/(4.0*PI)"
                           : "return " + f + "*Multiplier/(4.0*PI)");
}
// 64 sine/cosine steps per iteration of a loop whose condition the compiler cannot decide (σa is
// never negative): on llvmpipe the driver stops it after 65 535 iterations, about 5 s for the
// 512 radii of the pencil profile on a 2-core machine; elsewhere it never ends.
const char* kSlowLoop = "    float slow = Xo.x;\n"
                        "#define STEP slow = sin(slow * 1.37 + 0.11) + cos(slow * 0.73);\n"
                        "#define STEP4 STEP STEP STEP STEP\n"
                        "#define STEP16 STEP4 STEP4 STEP4 STEP4\n"
                        "    while (SigmaA.x >= 0.0) { STEP16 STEP16 STEP16 STEP16 }\n"
                        "    if (slow > 1e30) return vec3(slow);";

struct ProbeFixture : ::testing::Test {
    void SetUp() override {
        testsupport::context();
        app::setModelProbeExecutable(BW_EXE);
        ::setenv("BSSRDF_WORKBENCH_PROBE_SECONDS", "1", 1);
        // the check's time limit is what these tests see: no loop budget (bssrdf/loop_budget.h)
        // stops the slow loop first (LoopBudget.* test the budget)
        ::setenv("BSSRDF_WORKBENCH_LOOP_BUDGET", "2147483648", 1);
        root = testsupport::makeProjectRoot(
            "probe_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()),
            {"dipole.bssrdf"});
        file = root / path;
        good = testsupport::readText(file);
    }
    void TearDown() override {
        app::resetModelProbes(); // the next test starts as a new process would (gtest_filter=*)
        app::setModelProbeExecutable({});
        ::unsetenv("BSSRDF_WORKBENCH_PROBE_SECONDS");
        ::unsetenv("BSSRDF_WORKBENCH_LOOP_BUDGET");
        fs::remove_all(root);
    }
    fs::path root, file;
    std::string path = "materials/dipole.bssrdf", good;
};

} // namespace

TEST_F(ProbeFixture, SlowModelTimesOutTheLastGoodVersionStaysThenTheFixIsAdopted) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    core::writeFile(file, withLoop(good, kSlowLoop));
    std::string error;
    const int whileChecking = updateUntil(wb, [&] {
        error = errorNaming(wb, path);
        return !error.empty();
    });
    EXPECT_NE(error.find("did not finish within 1 s"), std::string::npos) << error;
    EXPECT_NE(error.find("a loop that does not end?"), std::string::npos) << error;
    const int line = whileLine(withLoop(good, kSlowLoop));
    EXPECT_NE(error.find("the loop at line " + std::to_string(line) + " (while)"),
              std::string::npos)
        << error;
    // The main process never evaluated the model: updates came while the check ran (evaluating
    // it here would take about 5 s on llvmpipe, for ever on a GPU).
    EXPECT_GE(whileChecking, 1);
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base); // the last good version stays
    EXPECT_TRUE(wb.library().find(path)->usable());
    // fixed: checked again and adopted
    core::writeFile(file, scaled(good, 2.0));
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - 2 * base) < 1e-5 * base; });
    EXPECT_NEAR(valueAt0(wb, path), 2 * base, 1e-5 * base);
    EXPECT_TRUE(errorNaming(wb, path).empty()) << errorNaming(wb, path);
}

TEST_F(ProbeFixture, EndlessLoopIsRefusedNamingTheFile) {
    // Under the default loop budget (bssrdf/loop_budget.h) the check's own evaluation stops
    // both loops after the budget, on any driver, and names the loop. Without it, drivers
    // differ: llvmpipe's compiler drops what follows `while (true)` and llvmpipe cuts a loop on
    // a uniform after 65 535 iterations in all, Mesa's zink cuts each loop on its own after as
    // many (so the check's sentinel does not see it, and the model passed), a GPU runs until
    // the child is killed.
    ::unsetenv("BSSRDF_WORKBENCH_LOOP_BUDGET");
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    for (const char* loop : {"    while (true) {}",
                             "    float spin = 0.0;\n    while (SigmaA.x >= 0.0) { spin += 1.0; }\n"
                             "    if (spin < 0.0) return vec3(spin);"}) {
        core::writeFile(file, withLoop(good, loop));
        std::string error;
        const int whileChecking = updateUntil(wb, [&] {
            error = errorNaming(wb, path);
            return !error.empty();
        });
        // the entry is at the loop's line and names it
        const int line = whileLine(withLoop(good, loop));
        ASSERT_GT(line, 0);
        EXPECT_NE(error.find(path + ":" + std::to_string(line) + ":"), std::string::npos) << error;
        EXPECT_NE(
            error.find("the loop at line " + std::to_string(line) + " ran past the loop budget"),
            std::string::npos)
            << loop << ": " << error;
        EXPECT_GE(whileChecking, 1) << loop;
        EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base) << loop;
        core::writeFile(file, good); // good again (known: adopted without a check)
        updateUntil(wb, [&] { return errorNaming(wb, path).empty(); });
        EXPECT_TRUE(errorNaming(wb, path).empty());
        EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    }
}

TEST_F(ProbeFixture, UnchangedTextIsNotCheckedAgain) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    // the same text saved again (and a model's text seen before): adopted without a check
    core::writeFile(file, good);
    updateUntil(
        wb, [&] { return false; }, 400);
    EXPECT_FALSE(wb.library().checking());
    EXPECT_TRUE(wb.errors().empty());
    // a changed text with a loop is checked before it is adopted
    core::writeFile(file, scaled(good, 3.0));
    updateUntil(
        wb, [&] { return wb.library().checking(); }, 5000);
    EXPECT_TRUE(wb.library().checking());
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base); // not yet adopted
    updateUntil(wb, [&] { return !wb.library().checking(); });
    EXPECT_NEAR(valueAt0(wb, path), 3 * base, 1e-5 * base);
}

// Checks are made by one warm `probe-server` child, save after save; a check that runs out of
// time kills it and a new one takes the next check.
TEST_F(ProbeFixture, TheWarmServerChecksSaveAfterSaveAndIsReplacedAfterAHang) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    auto saveAndWait = [&](double factor) {
        core::writeFile(file, scaled(good, factor));
        updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - factor * base) < 1e-5 * base; });
        EXPECT_NEAR(valueAt0(wb, path), factor * base, 1e-5 * base) << factor;
    };
    const app::ProbeCounts before = app::probeCounts();
    saveAndWait(1.25);
    const int server = app::probeServerPid();
    EXPECT_GT(server, 0);
    saveAndWait(1.5);
    saveAndWait(1.75);
    app::ProbeCounts after = app::probeCounts();
    EXPECT_EQ(after.served - before.served, 3); // every save checked by the server
    EXPECT_EQ(after.ownProcess, before.ownProcess);
    EXPECT_EQ(app::probeServerPid(), server); // the same process throughout
    EXPECT_TRUE(wb.errors().empty());

    core::writeFile(file, withLoop(good, kSlowLoop));
    std::string error;
    updateUntil(wb, [&] {
        error = errorNaming(wb, path);
        return !error.empty();
    });
    EXPECT_NE(error.find("did not finish within 1 s"), std::string::npos) << error;
    const int replacement = app::probeServerPid();
    EXPECT_GT(replacement, 0);
    EXPECT_NE(replacement, server); // the stuck one was killed, a new one started
    EXPECT_NEAR(valueAt0(wb, path), 1.75 * base, 1e-5 * base); // the last good version stays

    saveAndWait(2.0);
    after = app::probeCounts();
    EXPECT_EQ(after.served - before.served, 5);
    EXPECT_EQ(app::probeServerPid(), replacement);
    EXPECT_TRUE(errorNaming(wb, path).empty()) << errorNaming(wb, path);
}

// A save while the server checks the version before: that check is given up (its server
// replaced, it may be stuck in it) and the newer version is checked and adopted.
TEST_F(ProbeFixture, ASaveDuringACheckReplacesItAndTheNewestVersionWins) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    const long evaluating = app::probeCounts().evaluating;
    core::writeFile(file, withLoop(good, kSlowLoop)); // would take about 5 s
    // until the check has read and built this version (had the next save landed before the
    // server read the file, the server would check that one, quickly, and stay)
    updateUntil(
        wb, [&] { return app::probeCounts().evaluating > evaluating; }, 5000);
    ASSERT_TRUE(wb.library().checking());
    const int busy = app::probeServerPid();
    core::writeFile(file, scaled(good, 4.0));
    const int whileChecking =
        updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - 4 * base) < 1e-5 * base; });
    EXPECT_NEAR(valueAt0(wb, path), 4 * base, 1e-5 * base);
    EXPECT_GE(whileChecking, 1); // no update() waited for a check, the busy one or the new one
    EXPECT_NE(app::probeServerPid(), busy);
    EXPECT_TRUE(errorNaming(wb, path).empty()) << errorNaming(wb, path);
}

// The server's protocol, as the workbench speaks it: each request answered in order with the
// output of `probe-model` and `done CODE`; bad requests are answered, not fatal; the end of
// its input ends it with status 0.
TEST(ProbeServer, AnswersEachRequestInOrderAndEndsWithItsInput) {
    const fs::path root = BW_SOURCE_ROOT;
    const std::string sep(1, app::kProbeFieldSeparator), end(1, app::kProbeRequestEnd);
    app::ChildProcess server({BW_EXE, "probe-server"}, "probe-server", true);
    const std::string model = (root / "materials/dipole.bssrdf").string();
    ASSERT_TRUE(server.send(root.string() + sep + model + end));
    ASSERT_TRUE(server.send(root.string() + sep + "/nonexistent/x.bssrdf" + end));
    ASSERT_TRUE(server.send(root.string() + sep + model + sep + "--samples" + sep + "0" + end));
    ASSERT_TRUE(server.send(root.string() + end)); // no file
    ASSERT_TRUE(server.send(root.string() + sep + model + sep + "--samples" + sep + "7" + end));
    core::Stopwatch sw;
    auto count = [&](const std::string& what) {
        size_t n = 0;
        for (size_t at = server.output().find(what); at != std::string::npos;
             at = server.output().find(what, at + 1))
            ++n;
        return n;
    };
    while (count("probe-model: done") < 5 && sw.ms() < 60000 && !server.poll())
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const std::string& out = server.output();
    ASSERT_EQ(count("probe-model: done"), 5u) << out;
    EXPECT_EQ(out.rfind("probe-model: ready\n", 0), 0u) << out;
    const size_t d[5] = {out.find("done 0"), out.find("done 1"), out.find("done 2"),
                         out.find("done 1", out.find("done 2")),
                         out.find("done 0", out.find("done 2"))};
    for (int i = 0; i < 5; ++i)
        ASSERT_NE(d[i], std::string::npos) << i << "\n" << out;
    EXPECT_TRUE(d[0] < d[1] && d[1] < d[2] && d[2] < d[3] && d[3] < d[4]) << out;
    EXPECT_NE(out.find("/nonexistent/x.bssrdf: cannot open"), std::string::npos) << out;
    EXPECT_NE(out.find("--samples: Value 0 not in range"), std::string::npos) << out;
    EXPECT_EQ(count("probe-model: ok"), 2u) << out;
    // the end of its input: it ends, status 0
    server.closeInput();
    while (!server.poll() && sw.ms() < 60000)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ASSERT_TRUE(server.done());
    EXPECT_EQ(server.exitCode(), 0) << server.output();
}

// The server killed from outside in the middle of a check (a crash of the driver would look the
// same): the check's verdict names the signal, the last good version stays, and the next save
// is checked by a new server.
TEST_F(ProbeFixture, AServerThatDiesMidCheckIsReportedAndReplaced) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    core::writeFile(file, withLoop(good, kSlowLoop)); // about 5 s of evaluation
    updateUntil(
        wb, [&] { return wb.library().checking(); }, 5000);
    ASSERT_TRUE(wb.library().checking());
    const int server = app::probeServerPid();
    ASSERT_GT(server, 0);
    ASSERT_EQ(::kill(server, SIGKILL), 0);
    std::string error;
    updateUntil(wb, [&] {
        error = errorNaming(wb, path);
        return !error.empty();
    });
    EXPECT_NE(error.find("ended with signal 9"), std::string::npos) << error;
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    const int replacement = app::probeServerPid();
    EXPECT_GT(replacement, 0);
    EXPECT_NE(replacement, server);
    core::writeFile(file, scaled(good, 5.0));
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - 5 * base) < 1e-5 * base; });
    EXPECT_NEAR(valueAt0(wb, path), 5 * base, 1e-5 * base);
    EXPECT_EQ(app::probeServerPid(), replacement);
    EXPECT_TRUE(errorNaming(wb, path).empty()) << errorNaming(wb, path);
}

// A model without a loop cannot run away (straight-line code ends; the GLSL around it bounds its
// own loops), so once a check passed in its frame (templates, includes, parameters) its saves are
// adopted at once; a save that adds a loop is checked (one hidden in a macro is refused), and so
// is a loop-free save after the GLSL around the model changed (a template edited), until a check
// passed in that frame.
TEST_F(ProbeFixture, ALoopFreeModelInAFrameThatPassedIsAdoptedWithoutACheck) {
    app::Workbench wb(root, true); // its start-up check passes in this frame
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    auto checks = [] {
        const app::ProbeCounts c = app::probeCounts();
        return c.served + c.ownProcess;
    };
    auto saveAndWait = [&](double factor, bool looped) {
        core::writeFile(file, scaled(good, factor, looped));
        updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - factor * base) < 1e-5 * base; });
        EXPECT_NEAR(valueAt0(wb, path), factor * base, 1e-5 * base) << factor;
    };
    long before = checks(), unneeded = app::probeCounts().unneeded;
    const long codeOnly = app::probeCounts().codeOnly;
    saveAndWait(1.5, false);
    EXPECT_EQ(checks(), before);
    EXPECT_EQ(app::probeCounts().unneeded - unneeded, 1);
    // not checked, but its code generated by the free server first (`probe-model --code-only`)
    EXPECT_EQ(app::probeCounts().codeOnly - codeOnly, 1);

    saveAndWait(2.5, true); // a loop: checked
    EXPECT_EQ(checks() - before, 1);
    // a loop the scan cannot see, made in a macro: refused when parsed (the loop budget could
    // not guard it), the last good version stays
    const std::string hidden = replaced(scaled(good, 2.75, true), "for (int k",
                                        "#define LOOP(a, b) a##b\n    LOOP(fo, r) (int k");
    core::writeFile(file, hidden);
    std::string error;
    updateUntil(wb, [&] {
        error = errorNaming(wb, path);
        return !error.empty();
    });
    const size_t define = hidden.find("#define LOOP");
    const long defineLine = 1 + std::count(hidden.begin(), hidden.begin() + long(define), '\n');
    EXPECT_NE(error.find(path + ":" + std::to_string(defineLine) + ":"), std::string::npos)
        << error;
    EXPECT_NE(error.find("a macro that loops"), std::string::npos) << error;
    EXPECT_NEAR(valueAt0(wb, path), 2.5 * base, 1e-5 * base);
    EXPECT_EQ(checks() - before, 1);

    // the template the check evaluates changed: a new frame, so a loop-free save is checked
    const fs::path tmpl = root / "shaders/pencil_profile.comp";
    core::writeFile(tmpl, testsupport::readText(tmpl) + "\n// edited\n");
    updateUntil(
        wb, [&] { return false; }, 300);
    before = checks();
    unneeded = app::probeCounts().unneeded;
    saveAndWait(3.5, false);
    EXPECT_EQ(checks() - before, 1);
    EXPECT_EQ(app::probeCounts().unneeded, unneeded);
    // and once it passed in that frame, the next loop-free save needs none again
    saveAndWait(4.5, false);
    EXPECT_EQ(checks() - before, 1);
    EXPECT_EQ(app::probeCounts().unneeded - unneeded, 1);
    EXPECT_TRUE(wb.errors().empty());
}

// A loop-free save needs no check; the server only generates its code first, and the save is
// adopted however that ends: here the server is killed before it answers (stopped first, so that
// it cannot answer on a fast driver), the model is adopted all the same, no error is shown, and
// a new server is ready for the next check.
TEST_F(ProbeFixture, ALoopFreeSaveIsAdoptedWhenTheServerGeneratingItsCodeEnds) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    const int server = app::probeServerPid();
    ASSERT_GT(server, 0);
    ASSERT_EQ(::kill(server, SIGSTOP), 0);
    const long codeOnly = app::probeCounts().codeOnly;
    core::writeFile(file, scaled(good, 1.5, false));
    updateUntil(wb, [&] { return app::probeCounts().codeOnly > codeOnly; });
    ASSERT_EQ(app::probeCounts().codeOnly - codeOnly, 1);
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base); // waiting for the server's answer
    ASSERT_EQ(::kill(server, SIGKILL), 0);
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - 1.5 * base) < 1e-5 * base; });
    EXPECT_NEAR(valueAt0(wb, path), 1.5 * base, 1e-5 * base);
    EXPECT_TRUE(wb.errors().empty());
    EXPECT_NE(app::probeServerPid(), server);
    const std::vector<core::LogEntry> log = core::logSnapshot();
    EXPECT_TRUE(std::any_of(log.begin(), log.end(), [](const core::LogEntry& e) {
        return e.text.find("its code was not generated in the check's process (the server "
                           "ended); adopted, as it needs no check") != std::string::npos;
    }));
    // and a save with a loop is checked by the new server
    const long served = app::probeCounts().served;
    core::writeFile(file, scaled(good, 2.5, true));
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - 2.5 * base) < 1e-5 * base; });
    EXPECT_NEAR(valueAt0(wb, path), 2.5 * base, 1e-5 * base);
    EXPECT_EQ(app::probeCounts().served - served, 1);
}

// With the scene showing the model, the server generates the code of the renderer's traversal
// program too, after the plot's (a loop-free save) or after a check that passed (a save with a
// loop); the plot takes the save at once, the scene keeps its last frame while the server works
// (here held up by stopping it), then renders the new model.
static void sceneTakesTheSaveOnceTheServerHasItsTraversalCode(const fs::path& root,
                                                              const fs::path& file,
                                                              const std::string& path,
                                                              const std::string& good,
                                                              bool looped) {
    app::Workbench wb(root, true);
    app::SceneSettings& ss = wb.scene().settings();
    ss.enabled = true;
    testsupport::useSmallScene(ss);
    wb.finishScene();
    ASSERT_TRUE(wb.scene().hasFrame());
    auto exitance = [&] {
        const render::Readback rb = wb.scene().readback();
        double sum = 0;
        for (const glm::vec4& m : rb.exitance)
            sum += m.w > 0 ? double(m.r) + m.g + m.b : 0.0;
        return sum;
    };
    const double base = valueAt0(wb, path), total = exitance();
    ASSERT_GT(total, 0.0);
    const app::ProbeCounts before = app::probeCounts();
    // a factor new to the driver's shader cache, so that the traversal's code takes a while
    const double factor = (looped ? 3.0 : 2.0) + double(::getpid() % 100000) * 1e-7;
    core::writeFile(file, scaled(good, factor, looped));
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - factor * base) < 1e-5 * base; });
    ASSERT_NEAR(valueAt0(wb, path), factor * base, 1e-5 * base); // the plot has it
    EXPECT_EQ(app::probeCounts().codeOnly - before.codeOnly, looped ? 0 : 1);
    EXPECT_EQ(app::probeCounts().served - before.served, looped ? 1 : 0); // checked there
    const int server = app::probeServerPid();
    ASSERT_GT(server, 0);
    if (app::rendererCodePending(path) && ::kill(server, SIGSTOP) == 0) {
        updateUntil(
            wb, [] { return false; }, 500);
        EXPECT_TRUE(app::rendererCodePending(path));
        EXPECT_FALSE(wb.scene().rendering());
        EXPECT_NEAR(exitance(), total, 1e-6 * total); // the last frame stays
        ::kill(server, SIGCONT);
    } else {
        std::printf("the server had the traversal's code at once: the wait is not exercised\n");
    }
    updateUntil(wb, [&] {
        return !app::rendererCodePending(path) && !wb.scene().rendering() &&
               std::abs(exitance() / total - factor) < 1e-4 * factor;
    });
    EXPECT_FALSE(app::rendererCodePending(path));
    // the server generated it (once the scene had the model, its answer was read)
    EXPECT_EQ(app::probeCounts().traversalCode - before.traversalCode, 1);
    EXPECT_NEAR(exitance() / total, factor, 1e-4 * factor);
    EXPECT_EQ(app::probeServerPid(), server); // the same server, free for the next check
    EXPECT_TRUE(wb.errors().empty());
}

TEST_F(ProbeFixture, TheSceneTakesALoopFreeSaveOnceTheServerHasItsTraversalCode) {
    sceneTakesTheSaveOnceTheServerHasItsTraversalCode(root, file, path, good, false);
}

TEST_F(ProbeFixture, TheSceneTakesACheckedSaveOnceTheServerHasItsTraversalCode) {
    sceneTakesTheSaveOnceTheServerHasItsTraversalCode(root, file, path, good, true);
}

// A loop that only the inversion reaches (in DiffuseReflectance) is checked too: the check
// evaluates the inversion program whenever init() or DiffuseReflectance() can reach a loop
// (bssrdf::inversionMayLoop), and refuses this one; the last good version stays.
TEST_F(ProbeFixture, ALoopInDiffuseReflectanceIsCheckedThroughTheInversion) {
    app::Workbench wb(root, true);
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);
    const std::string spinning =
        replaced(good, "    vec3 T = sqrt(3.0*(1.0 - AlphaPrime));",
                 "    float spin = 0.0;\n    while (SigmaA.x >= 0.0) { spin += 1.0; }\n"
                 "    vec3 T = sqrt(3.0*(1.0 - AlphaPrime)) + vec3(spin < 0.0 ? spin : 0.0);");
    ASSERT_NE(spinning, good);
    core::writeFile(file, spinning);
    std::string error;
    updateUntil(wb, [&] {
        error = errorNaming(wb, path);
        return !error.empty();
    });
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find("line " + std::to_string(whileLine(spinning))), std::string::npos)
        << error;
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base); // the last good version stays
}

// The texture-space renderer (the Render panel's, texspace_stage.h) dispatches the traversal
// program too: while the server generates its code (held up here for 2 s, so that any driver
// shows the wait), a changed model waits as the scene's does, its last image stays and its run
// pauses; then it renders the new model. (Without the wait it took the model at once and
// generated the code on this thread.)
TEST_F(ProbeFixture, TextureSpaceTakesASaveOnceTheServerHasItsTraversalCode) {
    ::setenv("BSSRDF_WORKBENCH_PROBE_TRAVERSAL_DELAY_MS", "2000", 1); // read by the server
    app::Workbench wb(root, true);
    ::unsetenv("BSSRDF_WORKBENCH_PROBE_TRAVERSAL_DELAY_MS");
    app::SceneSettings& ss = wb.scene().settings();
    ss.enabled = true;
    testsupport::useSmallScene(ss);
    wb.finishScene();
    app::TextureSpaceSettings& ts = wb.textureSpaceSettings();
    ts.enabled = true;
    ts.sampling.textureSize = 128;
    ts.sampling.samples = 400;
    ts.sampling.sampleSets = 2;
    wb.finishTextureSpace();
    auto sum = [&] {
        const litsphere::Image img = wb.textureSpace().radiance();
        double s = 0;
        for (float v : img.mean)
            s += double(v);
        return s;
    };
    const double base = valueAt0(wb, path), total = sum();
    ASSERT_GT(total, 0.0);
    const long traversal = app::probeCounts().traversalCode;
    const double factor = 2.0 + double(::getpid() % 100000) * 1e-7;
    core::writeFile(file, scaled(good, factor, false));
    updateUntil(wb, [&] { return std::abs(valueAt0(wb, path) - factor * base) < 1e-5 * base; });
    ASSERT_NEAR(valueAt0(wb, path), factor * base, 1e-5 * base); // the plot has it
    ASSERT_TRUE(app::rendererCodePending(path));
    updateUntil(
        wb, [] { return false; }, 500);
    EXPECT_TRUE(app::rendererCodePending(path));
    EXPECT_NEAR(sum(), total, 1e-6 * total); // the last image stays
    updateUntil(wb, [&] {
        return !app::rendererCodePending(path) && wb.textureSpace().pipeline()->done() &&
               std::abs(sum() / total - factor) < 1e-3 * factor;
    });
    EXPECT_EQ(app::probeCounts().traversalCode - traversal, 1);
    EXPECT_NEAR(sum() / total, factor, 1e-3 * factor);
    EXPECT_TRUE(wb.errors().empty());
}
