// bench reload: edits a model file like an editor (temp file + rename) and measures the time
// from the file's modification time to the end of the first UI frame that shows the result
// (glFinish), on a headless context. Target (foundation issue): <= 150 ms on llvmpipe for a
// 512-sample plot, i.e. with the mesh pipeline off. Passes, in one process: the plot editing the
// dipole as it is (no loop: not checked once a check passed in its frame; the check's server
// generates its code while it is free, and the model is adopted when that is done), the plot
// editing it with a loop (the check of the changed model in a child process at every save,
// model_probe_process.h, kept warm between saves), the plot without any check (and the ratios
// of the medians), the plot with its frames paced like the windowed GUI's (a sleep of up to
// kFrameWaitSeconds before each, ended by a save or the child's output) editing the dipole as it
// is and with a loop, and with a loop again with the sleep ended by a save only (as before the
// child's output woke the window), then the default scene (the bunny through the point-cloud
// pipeline, the Render panel floating beside the plot) with the check, editing the dipole as it
// is and with a loop, for information: there a save also rebuilds every program of the scene
// that uses the model (the scene takes it one frame after the plot, or once the check's server
// has its traversal program's code) and renders the scene again, and each run prints when the
// scene had rendered it and the longest frame until then. Between edits the frames run until
// nothing changes and the scene is not rendering. Each save lands just before a frame: in the
// windowed GUI the file watcher's wake (core::FileWatcher::setWake) starts a frame when a save
// lands; while frames run back to back (a progressive reference) a save waits half a frame on
// average besides.
#include "bench/bench.h"

#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "gui/gui.h"
#include "gui/panels/registry.h"
#include "pipeline/workbench.h"
#include "probe/model_probe_process.h"
#include "probe/output_wake.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include <sys/stat.h>
#include <unistd.h>

namespace app {
namespace fs = std::filesystem;

namespace {
// Where a save's time goes, in the order it is spent: the timings the workbench records
// (gl::recordTiming, ScopedStageTimer) under these names. The check runs in its own process
// while this one compiles, so the parts overlap and do not add up to the latency.
const char* const kParts[][2] = {
    {"hot reload: file event", "file event"},
    {"hot reload: parse", "parse"},
    {"hot reload: compile (every consumer)", "compile"},
    {"hot reload: driver code generation", "code generation"},
    {"hot reload: model check", "model check"},
    {"hot reload: code generation by the server", "code generation by the server"},
    {"pencil plot", "first dispatch (pencil plot)"},
};

std::map<std::string, gl::StageTiming> timingsByName() {
    std::map<std::string, gl::StageTiming> out;
    for (const gl::StageTiming& t : gl::timings())
        out[t.stage] = t;
    return out;
}

// "file event 41.2, parse 0.3, ..." for the parts measured since `before`; the parts in `sums`.
std::string partsSince(const std::map<std::string, gl::StageTiming>& before,
                       std::map<std::string, std::vector<double>>& sums) {
    const auto now = timingsByName();
    std::string line;
    for (const auto& [name, label] : kParts) {
        const auto it = now.find(name);
        const auto was = before.find(name);
        if (it == now.end() || (was != before.end() && was->second.runs == it->second.runs))
            continue;
        char b[96];
        std::snprintf(b, sizeof b, "%s%s %.1f", line.empty() ? "" : ", ", label, it->second.cpuMs);
        line += b;
        sums[label].push_back(it->second.cpuMs);
    }
    return line;
}

// Seconds since the epoch, as a file's modification time counts them.
double wallSeconds() {
    using namespace std::chrono;
    return duration<double>(system_clock::now().time_since_epoch()).count();
}

// The windowed GUI's pacing while anything moves (gui/frame_pacing.h; a save's wake starts that):
// before each frame it sleeps up to kFrameWaitSeconds unless a wake ends the sleep; the bench
// wakes it from the same sources the window is woken by (the file watcher, and with childWakes a
// child's output: the check's verdict).
class WindowPacing {
  public:
    WindowPacing(Workbench& wb, bool childWakes) : m_wb(wb) {
        m_wb.wakeOnFileChanges([this] { wake(); });
        if (childWakes) wakeOnChildOutput([this] { wake(); });
    }
    ~WindowPacing() {
        m_wb.wakeOnFileChanges({});
        wakeOnChildOutput({});
    }
    WindowPacing(const WindowPacing&) = delete;
    WindowPacing& operator=(const WindowPacing&) = delete;
    void sleep() {
        std::unique_lock<std::mutex> lock(m_mutex);
        m_cv.wait_for(lock, std::chrono::duration<double>(kFrameWaitSeconds),
                      [this] { return m_woken; });
        m_woken = false;
    }

  private:
    void wake() {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_woken = true;
        }
        m_cv.notify_all();
    }
    Workbench& m_wb;
    std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_woken = false;
};

// The factors the edits scale the dipole by: floats in [1, 1.5), each one new in this process and
// drawn at random from 2^22, so that a run does not meet the driver's on-disk shader cache entries
// of an earlier run (Mesa keys them by the GLSL text and the generated code), which would skip
// the compile and the code generation the bench is there to measure.
class EditFactors {
  public:
    std::string next() {
        for (;;) {
            const float f = 1.0f + float(m_rng() >> 42) * 0x1p-23f; // 22 random bits: [1, 1.5)
            if (!m_used.insert(f).second) continue;
            // every float exactly, and a float literal in GLSL (1 prints as "1")
            const std::string text = core::formatNumber(f, 9);
            return text.find('.') == std::string::npos ? text + ".0" : text;
        }
    }

  private:
    std::mt19937_64 m_rng{std::random_device{}()};
    std::set<float> m_used;
};

// Frames until five in a row change nothing, the scene is not rendering and not waiting for the
// code of its traversal program (at most 60 s);
// returns the longest in ms, and in `lastChange` (when given) the wall-clock time at the end of
// the last frame that changed something or rendered, in seconds since the epoch.
double settle(Workbench& wb, HeadlessGui& gui, double* lastChange = nullptr) {
    core::Stopwatch clock;
    double longest = 0;
    for (int quiet = 0; quiet < 5 && clock.ms() < 60000;) {
        core::Stopwatch f;
        const bool busy = gui.frame() || wb.scene().rendering() ||
                          rendererCodePending(wb.library().entries().at(0).displayPath);
        quiet = busy ? 0 : quiet + 1;
        longest = std::max(longest, f.ms());
        if (busy && lastChange) {
            glFinish();
            *lastChange = wallSeconds();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return longest;
}

// Edits `file` `runs` times and returns the sorted save -> new pixels latencies in ms; the
// longest frame in `longestFrame`. `factors` makes every edit's text new.
// withLoop: the edit puts the factor in a one-iteration loop, so the model is checked at every
// save (a loop-free one is not, once a check passed in its frame: bssrdf::probeFrameKey).
// pacing: frames paced like the window's instead of back to back.
// settled: when given, each run's save -> the end of the last frame that changed something (the
// scene's re-rendered frame, when the scene runs), in ms.
std::vector<double> timeEdits(Workbench& wb, HeadlessGui& gui, const fs::path& file,
                              const std::string& model, int runs, EditFactors& factors,
                              double& longestFrame, bool withLoop = false,
                              WindowPacing* pacing = nullptr,
                              std::vector<double>* settled = nullptr) {
    std::vector<double> latencies;
    std::map<std::string, std::vector<double>> parts;
    const std::string anchor = "return Multiplier/(4.0*PI)";
    for (int run = 0; run < runs; ++run) {
        const size_t at = model.find(anchor);
        const std::string factor = factors.next();
        const std::string statement =
            withLoop ? "float f = 0.0;\n    for (int k = 0; k < 1; ++k) f += " + factor +
                           ";\n    return f*Multiplier/(4.0*PI)"
                     : "return " + factor + "*Multiplier/(4.0*PI)";
        const std::string edited =
            model.substr(0, at) + statement + model.substr(at + anchor.size());
        // (a factor new to the driver's shader cache: compiled, generated and checked anew)
        const fs::path swp = file.parent_path() / ("." + file.filename().string() + ".swp");
        { std::ofstream(swp, std::ios::binary) << edited; }
        fs::rename(swp, file);
        struct stat st {};
        ::stat(file.c_str(), &st);
        const double saved = double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec);
        const long long gen = wb.library().entries().at(0).generation;
        const auto before = timingsByName();
        core::Stopwatch guard;
        int frames = 0;
        double lastFrameMs = 0, runLongest = 0;
        while (guard.ms() < 5000 + 1000 * modelProbeSeconds()) {
            if (pacing) pacing->sleep(); // the window sleeps before each frame
            core::Stopwatch f;
            bool changed = gui.frame();
            lastFrameMs = f.ms();
            longestFrame = std::max(longestFrame, lastFrameMs);
            runLongest = std::max(runLongest, lastFrameMs);
            ++frames;
            if (changed && wb.library().entries().at(0).generation > gen) break;
            if (!pacing) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        glFinish();
        const double now = wallSeconds();
        latencies.push_back((now - saved) * 1000.0);
        std::printf("run %2d  save -> new pixels %7.1f ms  (%d frames, longest %.1f ms, last "
                    "%.1f ms)\n",
                    run + 1, latencies.back(), frames, runLongest, lastFrameMs);
        std::printf("        ms: %s\n", partsSince(before, parts).c_str());
        parts["last frame"].push_back(lastFrameMs);
        parts["longest frame"].push_back(runLongest);
        // what the edit set off finishes before the next one (the scene adopts a changed
        // model one frame after the plot, and renders it in slices)
        double lastChange = now;
        const double settleLongest = settle(wb, gui, &lastChange);
        longestFrame = std::max(longestFrame, settleLongest);
        if (settled) {
            settled->push_back((lastChange - saved) * 1000.0);
            std::printf("        then until nothing changes: %.1f ms after the save, longest "
                        "frame %.1f ms\n",
                        settled->back(), settleLongest);
        }
    }
    std::printf("where the time goes (median ms over the runs; the check overlaps the compile):");
    std::vector<std::string> order;
    for (const auto& part : kParts)
        order.push_back(part[1]);
    order.push_back("last frame");
    order.push_back("longest frame");
    for (const std::string& label : order) {
        std::vector<double>& v = parts[label];
        if (v.empty()) continue;
        std::sort(v.begin(), v.end());
        std::printf(" %s %.1f;", label.c_str(), v[v.size() / 2]);
    }
    std::printf("\n");
    std::sort(latencies.begin(), latencies.end());
    return latencies;
}
} // namespace

int benchReload(const fs::path& root, int runs) {
    fs::path tmp = fs::temp_directory_path() / ("bw_bench_reload_" + std::to_string(::getpid()));
    fs::remove_all(tmp);
    fs::create_directories(tmp / "materials");
    fs::copy(root / "shaders", tmp / "shaders", fs::copy_options::recursive);
    fs::copy_file(root / "materials/presets.json", tmp / "materials/presets.json");
    fs::create_directory_symlink(fs::absolute(root / "third_party"),
                                 tmp / "third_party"); // the scene's mesh
    const std::string model = core::readFile(root / "materials/dipole.bssrdf");
    const fs::path file = tmp / "materials/dipole.bssrdf";
    core::writeFile(file, model);

    auto ctx = gl::createHeadlessContext(false);
    std::printf("GL: %s\n", ctx->renderer().c_str());
    Workbench wb(tmp, true);
    wb.plotSettings().samples = 512;
    HeadlessGui gui(wb, 1280, 860);
    // The scene's panels closed (so its pipeline does not run): the plot alone first, the
    // target's case.
    for (const PanelEntry& p : panelRegistry())
        if (p.needsScene) gui.ui().shared.open[static_cast<size_t>(p.id)] = false;
    for (int i = 0; i < 3; ++i)
        gui.frame(); // warm up: fonts, first compiles

    const fs::path checker = modelProbeExecutable();
    EditFactors factors;
    // pass 0: the dipole as it is (no loop: once a check passed in its frame, a save needs none);
    // pass 1: the dipole with a loop (checked at every save, in a child process); pass 2: no
    // check at all. Passes 0 and 1 as configured (the check on when the executable is set).
    const char* const kPasses[3] = {
        ("the plot, the dipole as it is (no loop: no check once one passed in its frame; the "
         "server generates its code):"),
        "the plot, the dipole with a loop (checked at every save in a child process):",
        "the plot, without any check:"};
    double medians[3] = {0, 0, 0};
    for (int pass = 0; pass < 3; ++pass) {
        setModelProbeExecutable(pass < 2 ? checker : fs::path());
        std::printf("%s\n", pass < 2 && checker.empty() ? "(the check is off)" : kPasses[pass]);
        const ProbeCounts before = probeCounts();
        double longest = 0;
        const std::vector<double> latencies =
            timeEdits(wb, gui, file, model, runs, factors, longest, pass == 1);
        const ProbeCounts after = probeCounts();
        medians[pass] = latencies[latencies.size() / 2];
        std::printf("reload latency: median %.1f ms, max %.1f ms over %d runs (checks %ld, not "
                    "needed %ld, of which the server generated the code of %ld); target 150 ms: "
                    "median/target = %.2f\n",
                    medians[pass], latencies.back(), runs,
                    (after.served + after.ownProcess) - (before.served + before.ownProcess),
                    after.unneeded - before.unneeded, after.codeOnly - before.codeOnly,
                    medians[pass] / 150.0);
    }
    setModelProbeExecutable(checker);
    std::printf("as it is / without any check: %.2f (%+.1f ms); with a loop, checked / without: "
                "%.2f (%+.1f ms)\n",
                medians[0] / medians[2], medians[0] - medians[2], medians[1] / medians[2],
                medians[1] - medians[2]);

    // The window's case: frames paced as the windowed GUI paces them. The dipole as it is (its
    // code generated by the server, the verdict waking the loop), then with a loop, with the
    // check's verdict waking the loop (as it does) and without (as before).
    if (!checker.empty()) {
        double paced[2] = {0, 0};
        for (int pass = 0; pass < 3; ++pass) {
            const bool withLoop = pass > 0, wakes = pass < 2;
            std::printf("the plot, the dipole %s, frames paced like the window's (up to %.0f ms "
                        "of sleep before each, ended by a save%s):\n",
                        withLoop ? "with a loop" : "as it is", 1000 * kFrameWaitSeconds,
                        wakes ? " or the child's output" : "; the verdict waits for its end");
            double longest = 0;
            WindowPacing pacing(wb, wakes);
            const std::vector<double> latencies =
                timeEdits(wb, gui, file, model, runs, factors, longest, withLoop, &pacing);
            if (withLoop) paced[wakes ? 1 : 0] = latencies[latencies.size() / 2];
            std::printf("reload latency, paced: median %.1f ms, max %.1f ms over %d runs; longest "
                        "frame %.1f ms\n",
                        latencies[latencies.size() / 2], latencies.back(), runs, longest);
        }
        std::printf("paced, with a loop, the verdict waking the loop / waiting for the sleep's "
                    "end: %.2f (%+.1f ms)\n",
                    paced[1] / paced[0], paced[1] - paced[0]);
    }

    // The scene: the Render panel floating beside the plot (so both are shown and the scene's
    // pipeline runs), built and rendered once before timing.
    std::printf("the default scene (the bunny, point-cloud pipeline, the Render panel floating "
                "beside the plot) as well%s:\n",
                checker.empty() ? "" : ", with the check");
    const size_t render = static_cast<size_t>(PanelId::Render);
    gui.ui().shared.workspace.floating[render] = true;
    gui.ui().shared.open[render] = true;
    core::Stopwatch build;
    while (!(wb.scene().hasFrame() && !wb.scene().rendering()) && build.ms() < 300000) {
        gui.frame();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (!wb.scene().hasFrame()) {
        std::printf("the scene did not render a frame within %.0f s (mesh %s, %zu points): this "
                    "pass is left out\n",
                    build.ms() / 1000, wb.scene().hasMesh() ? "loaded" : "not loaded",
                    wb.scene().cloud().points.size());
        fs::remove_all(tmp);
        return 1;
    }
    std::printf("(the scene built and rendered in %.1f s)\n", build.ms() / 1000);
    settle(wb, gui);
    // the dipole as it is (its code and the traversal's generated by the server), then with a
    // loop (checked by the server, which then generates the traversal's code)
    for (const bool withLoop : {false, true}) {
        double longest = 0;
        std::vector<double> settled;
        const std::vector<double> latencies =
            timeEdits(wb, gui, file, model, runs, factors, longest, withLoop, nullptr, &settled);
        std::sort(settled.begin(), settled.end());
        std::printf("reload latency with the scene, the dipole %s: the plot's new pixels median "
                    "%.1f ms, max %.1f ms; the scene re-rendered (nothing changing any more) "
                    "median %.1f ms, max %.1f ms over %d runs; longest frame %.1f ms (every "
                    "program of the scene that uses the model is rebuilt; no target)\n",
                    withLoop ? "with a loop" : "as it is", latencies[latencies.size() / 2],
                    latencies.back(), settled[settled.size() / 2], settled.back(), runs, longest);
    }
    fs::remove_all(tmp);
    return 0;
}

} // namespace app
