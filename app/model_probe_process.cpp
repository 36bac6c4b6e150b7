// Model checks in a child process (model_probe_process.h).
#include "model_probe_process.h"

#include "cli_probe.h"
#include "core/core.h"
#include "core/text.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <thread>

namespace app {
namespace fs = std::filesystem;

namespace {
fs::path& probeExe() {
    static fs::path exe;
    return exe;
}
// Keys whose check passed in this process.
std::set<std::string>& passedKeys() {
    static std::set<std::string> keys;
    return keys;
}
double nowMs() {
    using namespace std::chrono;
    return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}
std::string seconds(double s) {
    return core::formatNumber(s, 3) + " s";
}
std::string floats(const float* v, int n) {
    std::string s;
    for (int i = 0; i < n; ++i) {
        if (i > 0) s += ',';
        s += core::formatNumber(double(v[i]), 9);
    }
    return s;
}
// The child's last line that is not its protocol (its error message), without "error: " and the
// model's own display path (the Errors entry names it).
std::string lastMessage(const std::string& output, const std::string& display) {
    std::string last, line;
    for (size_t i = 0; i <= output.size(); ++i) {
        if (i < output.size() && output[i] != '\n') {
            line += output[i];
            continue;
        }
        if (!line.empty() && line.rfind(kProbeTag, 0) != 0) last = line;
        line.clear();
    }
    if (last.rfind("error: ", 0) == 0) last = last.substr(7);
    if (last.rfind(display + ": ", 0) == 0) last = last.substr(display.size() + 2);
    return last;
}
bool warnedUnavailable = false;
} // namespace

double modelProbeSeconds() {
    if (const char* s = std::getenv("BSSRDF_WORKBENCH_PROBE_SECONDS"); s && *s) {
        char* end = nullptr;
        const double v = std::strtod(s, &end);
        if (end != s && *end == '\0' && v > 0 && v < 1e6) return v;
    }
    return kModelProbeSeconds;
}

void setModelProbeExecutable(const fs::path& exe) {
    probeExe() = exe;
}
const fs::path& modelProbeExecutable() {
    return probeExe();
}

bssrdf::ProbeStarter makeProbeStarter(fs::path root,
                                      std::function<ProbeInputs(const fs::path&)> inputsFor) {
    return [root = std::move(root), inputsFor = std::move(inputsFor)](
               const fs::path& file, const bssrdf::Model& m, const bssrdf::ParamValues& values,
               const std::string& key) -> std::unique_ptr<bssrdf::PendingProbe> {
        if (probeExe().empty() || passedKeys().count(key)) return nullptr;
        const ProbeInputs in = inputsFor(file);
        const bssrdf::Builtins& b = in.builtins;
        std::vector<std::string> args = {probeExe().string(),
                                         "--root",
                                         root.string(),
                                         "probe-model",
                                         file.string(),
                                         "--sigma-a",
                                         floats(&b.sigmaA[0], 3),
                                         "--sigma-s",
                                         floats(&b.sigmaS[0], 3),
                                         "--g",
                                         floats(&b.g, 1),
                                         "--eta",
                                         floats(&b.ior, 1),
                                         "--scale",
                                         floats(&b.scale, 1),
                                         "--rmax",
                                         core::formatNumber(in.rMaxMm, 17),
                                         "--samples",
                                         std::to_string(in.samples)};
        for (const auto& [name, v] : values)
            if (m.findParam(name))
                args.insert(args.end(), {"--param", name + "=" + floats(&v[0], 3)});
        return std::make_unique<ModelProbeProcess>(args, core::relativeTo(file, root), key,
                                                   in.samples);
    };
}

ModelProbeProcess::ModelProbeProcess(const std::vector<std::string>& args, std::string display,
                                     std::string key, int evaluations)
    : m_child(args, display), m_display(std::move(display)), m_key(std::move(key)),
      m_evaluations(evaluations), m_limit(modelProbeSeconds()), m_startMs(nowMs()) {}

bssrdf::ProbeVerdict ModelProbeProcess::poll() {
    if (!m_child.done()) {
        m_child.poll();
        if (m_evalStartMs < 0 &&
            m_child.output().find(std::string(kProbeTag) + " evaluating") != std::string::npos)
            m_evalStartMs = nowMs();
    }
    if (m_child.done()) return verdict();
    const double now = nowMs();
    if (m_evalStartMs >= 0 && now - m_evalStartMs > 1000.0 * m_limit) {
        m_child.cancel();
        return {true, "Bssrdf() did not finish within " + seconds(m_limit) +
                          " (the pencil profile at " + std::to_string(m_evaluations) +
                          " radii with the current parameters, run in a separate process): a loop "
                          "that does not end?"};
    }
    if (m_evalStartMs < 0 && now - m_startMs > 1000.0 * kModelProbeStartSeconds) {
        m_child.cancel();
        return {true, "its check did not get to evaluate the model within " +
                          seconds(kModelProbeStartSeconds) + " (building its programs)"};
    }
    return {};
}

bssrdf::ProbeVerdict ModelProbeProcess::wait() {
    for (;;) {
        bssrdf::ProbeVerdict v = poll();
        if (v.done) return v;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

bssrdf::ProbeVerdict ModelProbeProcess::verdict() {
    const int code = m_child.exitCode();
    const std::string& out = m_child.output();
    if (code == 0) {
        if (out.find(std::string(kProbeTag) + " key " + m_key) == std::string::npos)
            return {true, "the file changed while its first evaluation was checked; it is "
                          "checked again when it is saved"};
        passedKeys().insert(m_key);
        return {true, ""};
    }
    if (code == kProbeLoopCut) return {true, lastMessage(out, m_display)};
    if (code == kProbeUnavailable) {
        // No headless context for the check: the model is adopted unchecked, said once.
        if (!warnedUnavailable)
            core::logError("models are adopted without the check of their first evaluation: " +
                           lastMessage(out, m_display));
        warnedUnavailable = true;
        return {true, ""};
    }
    if (code > 128)
        return {true, "the check of its first evaluation ended with signal " +
                          std::to_string(code - 128) + " (" + lastMessage(out, m_display) + ")"};
    return {true, "the check of its first evaluation failed: " + lastMessage(out, m_display)};
}

} // namespace app
