// The Fit stage (fit_stage.h).
#include "pipeline/fit_stage.h"

#include "core/core.h"
#include "core/relative_error.h"
#include "pipeline/model_stages.h"
#include "pipeline/scoring.h"

#include <chrono>
#include <cmath>
#include <limits>

namespace app {

std::vector<std::string> splitParams(const std::string& params) {
    std::vector<std::string> out;
    std::string cur;
    bool range = false; // after '=' one comma belongs to LO,HI
    for (char c : params) {
        if (c == ',' && !range) {
            if (!cur.empty()) out.push_back(cur);
            cur.clear();
            continue;
        }
        if (c == '=')
            range = true;
        else if (c == ',')
            range = false;
        cur += c;
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
}

FitStage::~FitStage() {
    stopWorker();
}

void FitStage::stopWorker() {
    m_cancel = true;
    m_cv.notify_all();
    if (m_worker.joinable()) m_worker.join();
    m_cancel = false;
    m_request.reset();
    m_answer.reset();
}

void FitStage::start(const FitInputs& in, const std::string& model,
                     const std::vector<std::string>& params, const FitSettings& s) {
    stopWorker();
    bssrdf::ModelEntry* e = in.library ? in.library->find(model) : nullptr;
    if (!e || !e->usable()) throw core::Error(model, 0, "not a usable model");
    std::vector<FitVariable> vars = fitVariables(*e->model, params);
    for (const FitVariable& v : vars)
        if (v.medium)
            throw core::Error("fit", 0,
                              "the Fit panel frees the model's parameters; fit the medium (" +
                                  v.label + ") with the `fit` command");
    if (!in.reference || in.reference->pathsDone == 0 || !in.params)
        throw core::Error("fit", 0, "the path-traced reference has no paths yet (start it)");
    const ReferenceSnapshot& ref = *in.reference;
    std::vector<FitTarget> targets;
    std::vector<std::string> names;
    const auto media = mediaOf(*in.params);
    for (int c = 0; c < 3; ++c) {
        const pathtrace::SlabResult& r = ref.channel[size_t(c)];
        const pathtrace::Medium& m = media[size_t(c)];
        const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
        // as the Scoreboard scores: a channel with an l_d the bins resolve
        if (!(std::isfinite(ld) && ld > 0) || r.rMid.size() < 2 ||
            r.rMid.front() > core::kRelErrFromLd * ld)
            continue;
        FitTarget t;
        t.preset = "current";
        t.channel = c;
        t.ldMm = ld;
        t.params = *in.params;
        t.edges = binEdges(r.rMid);
        for (size_t i = 0; i < r.rd.size(); ++i) {
            t.ref.push_back(r.rd[i] / (1 - r.specular));
            t.refSe.push_back(r.rdStderr[i] / (1 - r.specular));
        }
        t.refBatches = r.rdBatches.scaled(1 / (1 - r.specular)); // as ref
        targets.push_back(std::move(t));
        names.push_back(std::string(1, "RGB"[c]));
    }
    if (targets.empty())
        throw core::Error("fit", 0,
                          "no channel of the reference has an l_d its bins resolve (narrow the "
                          "plot range)");
    std::vector<double> start;
    for (const FitVariable& v : vars)
        start.push_back(e->values.at(v.param)[size_t(v.component)]);
    m_snap = FitSnapshot{};
    m_snap.model = e->displayPath;
    m_snap.vars = std::move(vars);
    m_snap.targets = names;
    m_targets = std::move(targets);
    m_settings = s;
    m_start = start;
    m_generation = uint64_t(e->generation);
    launch(start);
}

void FitStage::launch(const std::vector<double>& start) {
    m_snap.running = true;
    m_snap.result.reset();
    m_searched.reset();
    m_workerDone = false;
    m_worker = std::thread([this, start] {
        // the objective: hand the point to the GL thread (update) and wait for its answer
        const ObjectiveFn fn = [this](const std::vector<double>& x, std::string& problem) {
            std::unique_lock lock(m_mutex);
            m_request = x;
            m_answer.reset();
            m_cv.wait(lock, [this] { return m_answer.has_value() || m_cancel.load(); });
            if (!m_answer) return std::numeric_limits<double>::quiet_NaN();
            problem = m_answer->second;
            const double f = m_answer->first;
            m_answer.reset();
            return f;
        };
        const auto progress = [this](int, double best) {
            std::lock_guard lock(m_mutex);
            m_snap.trace.push_back(best);
        };
        SearchResult r = searchParameters(m_snap.vars, start, m_settings, fn, progress, &m_cancel);
        std::lock_guard lock(m_mutex);
        m_searched = std::move(r);
        m_workerDone = true;
    });
}

bool FitStage::update(const FitInputs& in) {
    if (!m_snap.running) return false;
    bssrdf::ModelEntry* e = in.library ? in.library->find(m_snap.model) : nullptr;
    if (!e || !e->usable()) {
        stopWorker();
        m_snap.running = false;
        m_snap.problem = m_snap.model + " is no longer usable: the fit stopped";
        return true;
    }
    if (uint64_t(e->generation) != m_generation) { // hot reload: again from the best point
        std::vector<double> from;
        {
            std::lock_guard lock(m_mutex);
            from = m_snap.bestX.empty() ? m_start : m_snap.bestX;
        }
        stopWorker();
        m_generation = uint64_t(e->generation);
        ++m_snap.restarts;
        launch(from);
        return true;
    }
    bool changed = false;
    core::Stopwatch clock;
    bssrdf::ParamValues values = e->values;
    for (int served = 0; served == 0 || clock.ms() < frameBudgetMs; ++served) {
        std::vector<double> x;
        {
            std::unique_lock lock(m_mutex);
            if (m_workerDone || !m_request) {
                // give a worker that is about to ask a moment, then leave it for the next frame
                m_cv.wait_for(lock, std::chrono::milliseconds(1));
                if (m_workerDone || !m_request) break;
            }
            x = std::move(*m_request);
            m_request.reset();
        }
        applyFit(m_snap.vars, x, values);
        std::string problem;
        std::vector<double> squared;
        relErrOnTargets(*e, values, m_targets, &problem, &squared);
        const double f = meanSquared(squared);
        {
            std::lock_guard lock(m_mutex);
            m_answer = std::make_pair(f, problem);
            if (std::isfinite(f) && (m_snap.bestX.empty() || f <= m_snap.trace.back()))
                m_snap.bestX = x;
        }
        m_cv.notify_all();
        changed = true;
    }
    bool done = false;
    {
        std::lock_guard lock(m_mutex);
        done = m_workerDone;
    }
    if (done) {
        if (m_worker.joinable()) m_worker.join();
        FitResult r;
        static_cast<SearchResult&>(r) = *m_searched;
        r.start = m_start;
        std::vector<double> squared;
        applyFit(m_snap.vars, r.start, values);
        r.relErrStart = relErrOnTargets(*e, values, m_targets, nullptr, &squared);
        r.startObjective = meanSquared(squared);
        applyFit(m_snap.vars, r.best, values);
        r.relErrBest = relErrOnTargets(*e, values, m_targets);
        // the fitted curve for the pencil plot (its range and samples now)
        bssrdf::ParamValues fitted = e->values;
        applyFit(m_snap.vars, r.best, fitted);
        if (in.rMaxMm > 0 && in.samples > 1 && in.params)
            m_snap.fitted = bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(),
                                                    *e->model, fitted, builtinsOf(*in.params),
                                                    bssrdf::radiusGrid(in.rMaxMm, in.samples));
        m_snap.fittedValues = fitted;
        m_snap.result = std::move(r);
        m_snap.running = false;
        changed = true;
    }
    return changed;
}

void FitStage::finish(const FitInputs& in) {
    while (m_snap.running)
        update(in);
}

void FitStage::capture(const FitInputs& in, const FitRequestSettings& request,
                       CaptureEntries& out) {
    if (request.model.empty()) return;
    if (!in.reference || in.reference->pathsDone == 0) {
        out.missing.push_back("fit: " + request.model + ": needs the path-traced reference");
        return;
    }
    FitSettings s;
    s.maxEvaluations = request.maxEvaluations;
    s.xtolRel = request.xtolRel;
    start(in, request.model, splitParams(request.params), s);
    finish(in);
    if (!m_snap.result)
        throw core::Error("fit", 0, m_snap.problem.empty() ? "no result" : m_snap.problem);
    const FitResult& r = *m_snap.result;
    CaptureEntry e = captureEntry(CaptureEntry::Kind::Csv, "fit", "row");
    e.relTol = 1e-4;
    e.absTol = 1e-7;
    e.note = "deterministic: the same reference and start give the same search (NLopt BOBYQA); "
             "the model is evaluated in float on the GPU";
    e.table.comments = {"fit of " + request.model + " (" + request.params +
                            ") to the reference: " + r.status,
                        "rows 0..n-1: variable i, start, fitted; then per target (R, G, B "
                        "resolved): -1 - channel, rel_err before, rel_err after"};
    e.table.columns = {"row", "a", "b"};
    for (size_t i = 0; i < r.best.size(); ++i)
        e.table.rows.push_back({double(i), r.start[i], r.best[i]});
    for (size_t t = 0; t < m_targets.size(); ++t)
        e.table.rows.push_back({-1.0 - m_targets[t].channel, r.relErrStart[t], r.relErrBest[t]});
    out.entries.push_back(std::move(e));
}

StageStatus FitStage::status() const {
    StageStatus st;
    std::lock_guard lock(m_mutex);
    st.running = m_snap.running;
    if (!m_snap.problem.empty()) st.problems.push_back(m_snap.problem);
    if (m_snap.result)
        for (const std::string& p : m_snap.result->problems)
            st.problems.push_back("the model is not finite at " + p);
    st.stats.emplace_back("evaluations", std::to_string(m_snap.trace.size()));
    return st;
}

void FitStage::cancel() {
    if (!m_snap.running) return;
    m_cancel = true;
    m_cv.notify_all();
}

FitSnapshot FitStage::snapshot() const {
    std::lock_guard lock(m_mutex);
    return m_snap;
}

bool FitStage::apply(bssrdf::ModelLibrary& library) {
    if (!m_snap.result || m_snap.result->best.empty()) return false;
    bssrdf::ModelEntry* e = library.find(m_snap.model);
    if (!e || !e->usable()) return false;
    applyFit(m_snap.vars, m_snap.result->best, e->values);
    return true;
}

} // namespace app
