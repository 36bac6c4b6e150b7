// Model checks in a child process (model_probe_process.h).
#include "probe/model_probe_process.h"

#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "probe/protocol.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
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
// The frame (bssrdf::probeFrameKey) of each key sent to a check, and the frames a check passed
// in: a loop-free model in one of those is adopted without a check.
std::map<std::string, std::string>& frameOfKey() {
    static std::map<std::string, std::string> frames;
    return frames;
}
std::set<std::string>& passedFrames() {
    static std::set<std::string> frames;
    return frames;
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

namespace {
// wait() of both kinds of check: poll every 2 ms until the verdict (each poll() applies the
// check's own time limits, so this ends).
bssrdf::ProbeVerdict pollUntilDone(bssrdf::PendingProbe& p) {
    for (;;) {
        bssrdf::ProbeVerdict v = p.poll();
        if (v.done) return v;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

// The time limits of a check (model_probe_process.h): "" while within them, else the verdict's
// message. evalStartMs < 0: the check has not started evaluating yet.
std::string overTime(double startMs, double evalStartMs, double limit, int evaluations) {
    const double now = nowMs();
    if (evalStartMs >= 0 && now - evalStartMs > 1000.0 * limit)
        return "Bssrdf() did not finish within " + seconds(limit) + " (the pencil profile at " +
               std::to_string(evaluations) +
               " radii with the current parameters, run in a separate process): a loop that "
               "does not end?";
    if (evalStartMs < 0 && now - startMs > 1000.0 * kModelProbeStartSeconds)
        return "its check did not get to evaluate the model within " +
               seconds(kModelProbeStartSeconds) + " (building its programs)";
    return "";
}

// Where the line `<tag> <what>` starts in `out`: at the start of a line and ended by a newline
// (an error message quoting a path cannot fake it); npos if nowhere.
size_t lineAt(const std::string& out, const std::string& what) {
    const std::string line = std::string(kProbeTag) + " " + what;
    size_t at = out.rfind("\n" + line);
    at = at == std::string::npos ? (out.rfind(line, 0) == 0 ? 0 : at) : at + 1;
    return at != std::string::npos && out.find('\n', at) != std::string::npos ? at
                                                                              : std::string::npos;
}

// The server's work on a model after its adoption: the traversal program's code
// (`probe-model [--code-only] --render-width …`), which the scene waits for.
struct Tail {
    std::shared_ptr<ChildProcess> child;
    size_t from = 0;
    std::string display;
    double startMs = 0;
};

// The warm server of this process and whether a check is under way in it.
struct Server {
    std::shared_ptr<ChildProcess> child;
    fs::path exe;
    bool busy = false;
    bool unavailable = false; // it found no GL context: checks run in their own processes
    std::optional<Tail> tail; // busy with it
    ProbeCounts counts;
};
Server& server() {
    static Server s;
    return s;
}
// An answer of the server that ended with the traversal program's code.
void countTraversalCode(const std::string& out) {
    if (lineAt(out, "traversal code generated") != std::string::npos)
        ++server().counts.traversalCode;
}
// (Re)starts the server: the one before, if any, is killed once no check holds it.
void startServer() {
    Server& s = server();
    s.child.reset();
    s.busy = false;
    s.tail.reset();
    s.exe = probeExe();
    if (s.exe.empty() || s.unavailable) return;
    try {
        s.child = std::make_shared<ChildProcess>(
            std::vector<std::string>{s.exe.string(), "probe-server"}, "probe-server", true);
        ++s.counts.serverStarts;
    } catch (const core::Error& e) {
        core::logInfo(std::string("no warm model check: ") + e.what());
    }
}

// One check under way in the warm server, or (codeOnly) the generation of a model's code that
// needs no check (`probe-model --code-only`): that one ends in adoption however it ends.
class ServedProbe : public bssrdf::PendingProbe {
  public:
    // traversal: the request asks for the traversal program's code after a check that passes.
    ServedProbe(std::shared_ptr<ChildProcess> child, size_t from, std::string display,
                std::string key, int evaluations, bool codeOnly, bool traversal)
        : m_child(std::move(child)), m_from(from), m_display(std::move(display)),
          m_key(std::move(key)), m_evaluations(evaluations), m_limit(modelProbeSeconds()),
          m_startMs(nowMs()), m_codeOnly(codeOnly), m_traversal(traversal) {}
    bool evaluates() const override { return !m_codeOnly; }
    // Given up before its verdict: the server may be stuck in it, so a fresh one replaces it.
    ~ServedProbe() override {
        if (!m_ended) end(true);
    }
    bssrdf::ProbeVerdict poll() override {
        if (m_ended) return {true, "the check was already decided"}; // not reached by the library
        m_child->poll();
        const std::string out = m_child->output().substr(m_from);
        const std::string tag(kProbeTag);
        if (m_evalStartMs < 0 && out.find(tag + " evaluating") != std::string::npos) {
            m_evalStartMs = nowMs();
            ++server().counts.evaluating;
        }
        // the answer's last line, `probe-model: done CODE`
        if (const size_t done = lineAt(out, "done "); done != std::string::npos) {
            const int code = std::atoi(out.c_str() + done + tag.size() + 6);
            countTraversalCode(out);
            end(false);
            if (m_codeOnly) return codeOnlyEnded(code == 0 ? "" : lastMessage(out, m_display));
            return probeVerdict(code, out.substr(0, done), m_display, m_key);
        }
        // The plot's code is there (code only), or the check passed and its request asked for
        // the traversal program's code: decided now, while the server goes on with that code
        // (the scene waits for it: rendererCodePending).
        const size_t decided = m_codeOnly    ? lineAt(out, "code generated")
                               : m_traversal ? lineAt(out, "ok")
                                             : std::string::npos;
        if (decided != std::string::npos) {
            m_ended = true;
            server().tail = Tail{m_child, m_from, m_display, nowMs()};
            if (m_codeOnly) return {true, ""};
            return probeVerdict(0, out.substr(0, decided), m_display, m_key);
        }
        if (m_child->done()) { // the server ended in the middle of the check
            const int code = m_child->exitCode() == 0 ? 1 : m_child->exitCode();
            if (code == kProbeUnavailable) server().unavailable = true;
            end(true);
            if (m_codeOnly) return codeOnlyEnded("the server ended");
            return probeVerdict(code, out, m_display, m_key);
        }
        const std::string late = overTime(m_startMs, m_evalStartMs, m_limit, m_evaluations);
        if (!late.empty()) {
            m_child->cancel();
            end(true);
            if (m_codeOnly) return codeOnlyEnded(late);
            return {true, late};
        }
        return {};
    }
    bssrdf::ProbeVerdict wait() override { return pollUntilDone(*this); }

  private:
    // The model needed no check: adopted whether or not the server generated its code (if not,
    // this process generates it at its first dispatch, as without a server).
    bssrdf::ProbeVerdict codeOnlyEnded(const std::string& why) {
        if (!why.empty())
            core::logInfo(m_display + ": its code was not generated in the check's process (" +
                          why + "); adopted, as it needs no check");
        return {true, ""};
    }
    void end(bool restart) {
        m_ended = true;
        Server& s = server();
        if (s.child != m_child) return; // the server was replaced meanwhile
        s.busy = false;
        if (restart) {
            m_child->cancel();
            startServer(); // warming up for the next check
        }
    }
    std::shared_ptr<ChildProcess> m_child;
    size_t m_from;
    std::string m_display, m_key;
    int m_evaluations;
    double m_limit, m_startMs, m_evalStartMs = -1;
    bool m_codeOnly, m_traversal;
    bool m_ended = false;
};

// Ends the server's work after an adoption when its answer came, the server ended or it ran
// past kRendererCodeSeconds (then a new server starts).
void pollTail() {
    Server& s = server();
    if (!s.tail) return;
    Tail& t = *s.tail;
    if (s.child != t.child) {
        s.tail.reset();
        return;
    }
    t.child->poll();
    if (const std::string out = t.child->output().substr(t.from);
        lineAt(out, "done ") != std::string::npos) {
        countTraversalCode(out);
        s.tail.reset();
        s.busy = false;
    } else if (t.child->done()) {
        core::logInfo(t.display + ": the check's server ended while it generated the traversal "
                                  "program's code");
        startServer();
    } else if (nowMs() - t.startMs > 1000.0 * kRendererCodeSeconds) {
        core::logInfo(t.display +
                      ": the check's server did not generate the traversal "
                      "program's code within " +
                      seconds(kRendererCodeSeconds) + "; the scene generates it itself");
        t.child->cancel();
        startServer();
    }
}

// The check in the warm server (started here when there is none); nullptr when it is busy with
// another check or cannot take this one: the caller runs it in its own process.
std::unique_ptr<bssrdf::PendingProbe> servedProbe(const fs::path& root,
                                                  const std::vector<std::string>& args,
                                                  const std::string& display,
                                                  const std::string& key, int evaluations,
                                                  bool codeOnly = false, bool traversal = false) {
    pollTail();
    Server& s = server();
    if (s.unavailable || s.busy) return nullptr;
    std::string request = root.string();
    for (const std::string& a : args)
        request += kProbeFieldSeparator + a;
    if (request.find(kProbeRequestEnd) != std::string::npos ||
        root.string().find(kProbeFieldSeparator) != std::string::npos)
        return nullptr; // a path holding the protocol's separators
    for (const std::string& a : args)
        if (a.find(kProbeFieldSeparator) != std::string::npos) return nullptr;
    request += kProbeRequestEnd;
    if (!s.child || s.exe != probeExe() || s.child->poll()) startServer();
    if (!s.child) return nullptr;
    const size_t from = s.child->output().size();
    if (!s.child->send(request)) {
        startServer();
        return nullptr;
    }
    s.busy = true;
    ++(codeOnly ? s.counts.codeOnly : s.counts.served);
    return std::make_unique<ServedProbe>(s.child, from, display, key, evaluations, codeOnly,
                                         traversal);
}
} // namespace

int probeServerPid() {
    const Server& s = server();
    return s.child && !s.child->done() ? int(s.child->pid()) : -1;
}
ProbeCounts probeCounts() {
    return server().counts;
}
void resetModelProbes() {
    passedKeys().clear();
    frameOfKey().clear();
    passedFrames().clear();
    warnedUnavailable = false;
    Server& s = server();
    const ProbeCounts counts = s.counts;
    s = Server{}; // its child, if no check holds it any more, is killed here
    s.counts = counts;
}
bool rendererCodePending(const std::string& display) {
    pollTail();
    const Server& s = server();
    return s.tail && s.tail->display == display;
}

bssrdf::ProbeStarter makeProbeStarter(fs::path root,
                                      std::function<ProbeInputs(const fs::path&)> inputsFor) {
    return [root = std::move(root), inputsFor = std::move(inputsFor)](
               const fs::path& file, const bssrdf::Model& m, const bssrdf::ParamValues& values,
               const std::string& key) -> std::unique_ptr<bssrdf::PendingProbe> {
        if (probeExe().empty() || passedKeys().count(key)) return nullptr;
        // a loop-free model in a frame that passed a check needs none (bssrdf::probeFrameKey)
        const std::string frame = bssrdf::probeFrameKey(m, shader::Sources(root));
        const ProbeInputs in = inputsFor(file);
        // the scene shows this model: its traversal program's code is generated by the server
        // too, after the plot's code or a passed check (not by a check in its own process,
        // whose verdict would wait for it)
        std::vector<std::string> renderArgs;
        if (in.renderWidth > 0 && in.renderHeight > 0 && !gl::driverShaderCacheOff())
            renderArgs = {"--render-width", std::to_string(in.renderWidth), "--render-height",
                          std::to_string(in.renderHeight)};
        if (!frame.empty() && passedFrames().count(frame)) {
            ++server().counts.unneeded;
            passedKeys().insert(key); // the same text again needs nothing either
            // Its code is still new to the driver: generated by the server when it is free and
            // the driver's on-disk shader cache can hand it over (the model is adopted when the
            // server has the plot's code, and this thread's first dispatch then finds it; the
            // scene, when it shows this model, waits for the traversal program's), else here
            // at the first dispatch.
            if (gl::driverShaderCacheOff()) return nullptr;
            std::vector<std::string> args = {file.string(), "--code-only"};
            args.insert(args.end(), renderArgs.begin(), renderArgs.end());
            return servedProbe(root, args, core::relativeTo(file, root), key, 0, true);
        }
        frameOfKey()[key] = frame;
        const bssrdf::Builtins& b = in.builtins;
        std::vector<std::string> args = {file.string(),
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
        const std::string display = core::relativeTo(file, root);
        std::vector<std::string> servedArgs = args;
        servedArgs.insert(servedArgs.end(), renderArgs.begin(), renderArgs.end());
        if (auto served =
                servedProbe(root, servedArgs, display, key, in.samples, false, !renderArgs.empty()))
            return served;
        args.insert(args.begin(), {probeExe().string(), "--root", root.string(), "probe-model"});
        ++server().counts.ownProcess;
        return std::make_unique<ModelProbeProcess>(args, display, key, in.samples);
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
            m_child.output().find(std::string(kProbeTag) + " evaluating") != std::string::npos) {
            m_evalStartMs = nowMs();
            ++server().counts.evaluating;
        }
    }
    if (m_child.done()) return probeVerdict(m_child.exitCode(), m_child.output(), m_display, m_key);
    const std::string late = overTime(m_startMs, m_evalStartMs, m_limit, m_evaluations);
    if (!late.empty()) {
        m_child.cancel();
        return {true, late};
    }
    return {};
}

bssrdf::ProbeVerdict ModelProbeProcess::wait() {
    return pollUntilDone(*this);
}

bssrdf::ProbeVerdict probeVerdict(int code, const std::string& out, const std::string& display,
                                  const std::string& key) {
    if (code == 0) {
        if (out.find(std::string(kProbeTag) + " key " + key) == std::string::npos)
            return {true, "the file changed while its first evaluation was checked; it is "
                          "checked again when it is saved"};
        passedKeys().insert(key);
        if (auto f = frameOfKey().find(key); f != frameOfKey().end() && !f->second.empty())
            passedFrames().insert(f->second);
        return {true, ""};
    }
    if (code == kProbeLoopCut) return {true, lastMessage(out, display)};
    if (code == kProbeUnavailable) {
        // No headless context for the check: the model is adopted unchecked, said once.
        if (!warnedUnavailable)
            core::logError("models are adopted without the check of their first evaluation: " +
                           lastMessage(out, display));
        warnedUnavailable = true;
        return {true, ""};
    }
    if (code > 128) {
        const std::string last = lastMessage(out, display);
        return {true, "the check of its first evaluation ended with signal " +
                          std::to_string(code - 128) + (last.empty() ? "" : " (" + last + ")")};
    }
    return {true, "the check of its first evaluation failed: " + lastMessage(out, display)};
}

} // namespace app
