// bssrdf model library with keep-last-good reload semantics.
#include "bssrdf/program_library.h"
#include "bssrdf/loop_sites.h"

#include "core/core.h"

#include <algorithm>
#include <cstdlib>

namespace bssrdf {
namespace fs = std::filesystem;

std::string Problem::text() const {
    return core::formatLocation(file, line, message);
}

ModelLibrary::ModelLibrary(fs::path root, std::vector<std::string> consumers)
    : m_root(std::move(root)), m_sources(m_root), m_consumers(std::move(consumers)) {}

std::string ModelLibrary::displayPathOf(const fs::path& file) const {
    return core::relativeTo(file, m_root);
}

void ModelLibrary::scanAll() {
    std::vector<fs::path> files;
    std::error_code ec;
    for (auto& e : fs::directory_iterator(m_root / "materials", ec))
        if (e.path().extension() == ".bssrdf") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (auto& f : files)
        reload(f);
}

ModelEntry* ModelLibrary::find(const std::string& key) {
    for (auto& e : m_entries)
        if (e.displayPath == key || (e.model && e.model->name == key) ||
            e.file.stem().string() == key)
            return &e;
    return nullptr;
}

ModelEntry& ModelLibrary::open(const fs::path& file) {
    reload(fs::absolute(file));
    for (auto& e : m_entries)
        if (fs::equivalent(e.file, file)) return e;
    throw core::Error(file.string(), 0, "cannot open model");
}

namespace {
// Records why a (re)load failed; the entry keeps its last good model and programs.
// A version under its check is dropped: it is older than what failed. The problem is reported by
// whoever lists the library's problems (the Errors panel, or the command that fails on it): the
// log keeps it at info level, so it is not printed twice.
void fail(ModelEntry& e, const core::Error& err) {
    e.pending.reset();
    e.problem = Problem{err.file().empty() ? e.displayPath : err.file(), err.line(), err.message()};
    core::logInfo(e.displayPath + ": " + (e.model ? "keeping the last good version: " : "") +
                  e.problem->text());
}
} // namespace

void ModelLibrary::load(ModelEntry& e) {
    Model parsed;
    core::Stopwatch parse;
    try {
        parsed = loadModel(e.file, e.displayPath);
    } catch (const core::Error& err) {
        return fail(e, err);
    }
    // the parts of a save's latency (bench reload prints them): parse, compile, code generation
    gl::recordTiming("hot reload: parse", parse.ms());
    for (const auto& n : parsed.notes)
        core::logInfo(n);
    PendingModel c;
    c.model = std::move(parsed);
    // The check starts first: its process builds and evaluates the model while this one builds
    // the consumers' programs (on another core), instead of after them.
    e.pending.reset(); // a newer version replaces one still under its check, which stops
    if (!startProbe(e, c)) return;
    core::Stopwatch compile;
    for (const auto& consumer : m_consumers) {
        if (consumer == "invert_rdr.comp" && !c.model.diffuseReflectance) continue;
        try {
            core::Stopwatch sw;
            c.programs[consumer] =
                buildModelProgram(c.model, consumer, m_sources, e.shaders[consumer]);
            core::logDebug("built " + consumer + " for " + e.displayPath + " in " +
                           std::to_string(sw.ms()) + " ms");
        } catch (const core::Error& err) {
            return fail(e, err); // `c` and its check (if any) end here
        }
    }
    gl::recordTiming("hot reload: compile (every consumer)", compile.ms());
    // The driver's code generation for the programs the first frame after adoption dispatches,
    // while the check runs: on llvmpipe 45-100 ms per program at its first dispatch. The check's
    // process generates what it evaluates from the same text and the driver's on-disk shader
    // cache gives it to this process (its first dispatch then takes 1 ms), so this thread goes on
    // drawing frames; it generates only the rest (model_probe.h, programsToWarmDuringCheck).
    if (c.probe) {
        core::Stopwatch generate;
        for (const std::string& consumer :
             programsToWarmDuringCheck(c.model, e.inversionInUse, gl::driverShaderCacheOff()))
            if (auto it = c.programs.find(consumer); it != c.programs.end())
                warmUp(it->second.id());
        gl::recordTiming("hot reload: driver code generation", generate.ms());
    }
    propose(e, std::move(c));
}

void ModelLibrary::rebuild(ModelEntry& e, const std::vector<std::string>& consumers) {
    PendingModel c;
    c.model = *e.model;
    c.newModel = false;
    for (const auto& consumer : consumers) {
        try {
            c.programs[consumer] =
                buildModelProgram(*e.model, consumer, m_sources, e.shaders[consumer]);
        } catch (const core::Error& err) {
            return fail(e, err);
        }
    }
    propose(e, std::move(c));
}

bool ModelLibrary::startProbe(ModelEntry& e, PendingModel& c) {
    if (!m_probe || c.probe) return true;
    try {
        const ParamValues values =
            e.model ? carryOver(c.model, *e.model, e.values) : defaultValues(c.model);
        c.probe = m_probe(e.file, c.model, values, probeKey(c.model, m_sources));
        c.checkStartMs = core::secondsSinceStart() * 1000.0;
    } catch (const core::Error& err) {
        fail(e, err);
        return false;
    }
    return true;
}

void ModelLibrary::propose(ModelEntry& e, PendingModel c) {
    e.pending.reset(); // a newer version replaces one still under its check, which stops
    if (!startProbe(e, c)) return;
    if (c.probe) {
        core::logInfo(e.displayPath + ": checking its first evaluation in a separate process");
        e.pending = std::make_unique<PendingModel>(std::move(c));
        return;
    }
    adopt(e, std::move(c));
}

void ModelLibrary::adopt(ModelEntry& e, PendingModel c) {
    if (c.newModel) {
        e.values = e.model ? carryOver(c.model, *e.model, e.values) : defaultValues(c.model);
        e.model = std::move(c.model);
        e.programs = std::move(c.programs);
        ++e.modelGeneration;
    } else {
        for (auto& [consumer, program] : c.programs)
            e.programs[consumer] = std::move(program);
    }
    if (e.problem) core::logInfo(e.displayPath + ": recovered");
    e.problem.reset();
    ++e.generation;
}

bool ModelLibrary::finishProbes(bool block) {
    bool changed = false;
    for (auto& e : m_entries) {
        if (!e.pending) continue;
        const ProbeVerdict v = block ? e.pending->probe->wait() : e.pending->probe->poll();
        if (!v.done) continue;
        std::unique_ptr<PendingModel> c = std::move(e.pending);
        gl::recordTiming(c->probe->evaluates() ? "hot reload: model check"
                                               : "hot reload: code generation by the server",
                         core::secondsSinceStart() * 1000.0 - c->checkStartMs);
        if (v.problem.empty()) {
            adopt(e, std::move(*c));
        } else if (const size_t at = v.problem.find("at line ");
                   v.problem.find("loop budget") != std::string::npos && at != std::string::npos) {
            // a loop that ran past its budget (loop_budget.h) names itself
            fail(e, core::Error(e.displayPath, std::atoi(v.problem.c_str() + at + 8), v.problem));
        } else if (v.problem.find("loop") != std::string::npos) {
            // a model that does not finish: name its loops, and put the entry at the first
            const std::vector<LoopSite> loops = loopSites(c->model);
            fail(e, core::Error(e.displayPath, loops.empty() ? 0 : loops.front().line,
                                loops.empty() ? v.problem
                                              : v.problem + " [" + describeLoops(loops) + "]"));
        } else {
            fail(e, core::Error(e.displayPath, 0, v.problem));
        }
        changed = true;
    }
    return changed;
}

bool ModelLibrary::pollProbes() {
    return finishProbes(false);
}

bool ModelLibrary::waitForProbes() {
    return finishProbes(true);
}

bool ModelLibrary::checking() const {
    return std::any_of(m_entries.begin(), m_entries.end(),
                       [](const ModelEntry& e) { return e.checking(); });
}

bool ModelLibrary::reload(const fs::path& fileIn) {
    fs::path file = fs::absolute(fileIn).lexically_normal();
    auto it = std::find_if(m_entries.begin(), m_entries.end(),
                           [&](const ModelEntry& e) { return e.file == file; });
    std::error_code ec;
    if (!fs::exists(file, ec)) {
        if (it == m_entries.end()) return false;
        core::logInfo(it->displayPath + ": deleted, model removed");
        m_entries.erase(it);
        return true;
    }
    if (it == m_entries.end()) {
        ModelEntry e;
        e.file = file;
        e.displayPath = displayPathOf(file);
        m_entries.push_back(std::move(e));
        it = std::prev(m_entries.end());
        std::sort(m_entries.begin(), m_entries.end(), [](const ModelEntry& a, const ModelEntry& b) {
            return a.displayPath < b.displayPath;
        });
        it = std::find_if(m_entries.begin(), m_entries.end(),
                          [&](const ModelEntry& x) { return x.file == file; });
    }
    load(*it);
    return true;
}

bool ModelLibrary::onFilesChanged(const std::vector<fs::path>& paths) {
    bool changed = false;
    std::vector<fs::path> others;
    for (const auto& p : paths) {
        if (p.extension() == ".bssrdf")
            changed |= reload(p);
        else
            others.push_back(p);
    }
    if (others.empty()) return changed;
    for (auto& e : m_entries) {
        // A table model's data file: the model is made again from it.
        if (e.model && std::any_of(e.model->dataFiles.begin(), e.model->dataFiles.end(),
                                   [&](const fs::path& f) {
                                       return std::any_of(others.begin(), others.end(),
                                                          [&](const fs::path& o) {
                                                              std::error_code ec;
                                                              return fs::equivalent(f, o, ec);
                                                          });
                                   })) {
            changed |= reload(e.file);
            continue;
        }
        std::vector<std::string> hit;
        for (const auto& [consumer, record] : e.shaders)
            if (record.dependencies.containsAny(others)) hit.push_back(consumer);
        if (hit.empty()) continue;
        if (e.problem || !e.model || e.pending)
            load(e); // the last load failed or is under its check: the file is read again
        else
            rebuild(e, hit);
        changed = true;
    }
    return changed;
}

} // namespace bssrdf
