// The BSSRDF slice stage (slice_stage.h).
#include "pipeline/slice_stage.h"

#include "bssrdf/conditioning.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pipeline/param_json.h"
#include "pipeline/reference_stage.h"

#include <algorithm>
#include <cmath>

namespace app {

pathtrace::EstimateSettings estimateSettings(const SliceSettings& s, const pathtrace::Medium& m) {
    pathtrace::EstimateSettings e;
    e.thetaIDeg = {s.thetaIDeg};
    const double sigmaTr = m.sigmaA + m.sigmaS * (1 - m.g); // σ′t
    const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * sigmaTr);
    e.bins.rMaxMm = s.rangeLd * (std::isfinite(ld) ? ld : 10.0 / sigmaTr);
    e.bins.rBins = s.rBins;
    e.bins.spacing = s.logR ? pathtrace::RadialSpacing::Log : pathtrace::RadialSpacing::Uniform;
    e.bins.thetaSBins = s.thetaSBins;
    e.bins.dirCosBins = s.dirCosBins;
    e.bins.dirPhiBins = s.dirPhiBins;
    e.paths = s.paths;
    e.seed = s.seed;
    e.estimator = s.estimator;
    e.orders = s.orders;
    e.exits.samples = s.exitSamples;
    return e;
}

SliceRunner::~SliceRunner() {
    cancel();
}

void SliceRunner::cancel() {
    m_cancel = true;
    if (m_thread.joinable()) m_thread.join();
    m_cancel = false;
    std::lock_guard lock(m_mutex);
    m_snapshot.running = false;
}

void SliceRunner::wait() {
    if (m_thread.joinable()) m_thread.join();
}

void SliceRunner::start(const pathtrace::Medium& m, const pathtrace::EstimateSettings& s) {
    cancel();
    {
        std::lock_guard lock(m_mutex);
        try {
            pathtrace::validate(m, "slice medium");
            pathtrace::validate(s);
            if (s.thetaIDeg.size() != 1)
                throw core::Error("slice", 0, "one incidence angle at a time");
        } catch (const core::Error& e) {
            m_snapshot.problem = e.what(); // the last table stays
            m_snapshot.running = false;
            ++m_version;
            return;
        }
        const std::string key = core::keyOf(m, s);
        if (key == m_runKey && m_doneChunk >= pathtrace::chunkCount(s)) {
            m_snapshot.problem.clear(); // the same run, finished: nothing to do
            ++m_version;
            return;
        }
        if (key != m_runKey) { // a new run; the same one resumes where it was cancelled
            m_runKey = key;
            m_doneTally = pathtrace::makeTally(s.bins);
            m_doneChunk = 0;
            SliceSnapshot fresh;
            fresh.medium = m;
            fresh.settings = s;
            fresh.settings.paths = 0;
            fresh.pathsTarget = s.paths;
            m_snapshot = std::move(fresh);
        }
        m_snapshot.problem.clear();
        m_snapshot.running = true;
    }
    ++m_version;
    m_thread = std::thread(&SliceRunner::run, this, m, s);
}

void SliceRunner::run(pathtrace::Medium m, pathtrace::EstimateSettings s) {
    pathtrace::BssrdfTally tally;
    uint64_t chunk = 0;
    {
        std::lock_guard lock(m_mutex);
        tally = m_doneTally;
        chunk = m_doneChunk;
    }
    const uint64_t chunks = pathtrace::chunkCount(s);
    const uint64_t resumedPaths = tally.paths;
    uint64_t batch = 1;
    core::Stopwatch clock;
    while (chunk < chunks && !m_cancel) {
        const uint64_t last = std::min(chunks, chunk + batch);
        const uint64_t before = tally.paths;
        pathtrace::BssrdfTally part = pathtrace::estimateChunks(
            m, s, 0, chunk, last,
            [&](uint64_t done) {
                std::lock_guard lock(m_mutex);
                m_snapshot.pathsDone = before + done;
            },
            &m_cancel);
        if (m_cancel) break; // a partial batch is dropped: the table stays a prefix of paths
        tally.merge(part);
        chunk = last;
        SliceSnapshot snap;
        snap.running = chunk < chunks;
        snap.medium = m;
        snap.settings = s;
        snap.settings.paths = tally.paths;
        snap.pathsDone = tally.paths;
        snap.pathsTarget = s.paths;
        snap.pathsPerSecond =
            double(tally.paths - resumedPaths) / std::max(1e-9, clock.ms() * 1e-3);
        snap.slice = pathtrace::finalize(tally, s.bins, s.thetaIDeg[0], m);
        snap.energy = pathtrace::energyProblem(*snap.slice, s.orders);
        {
            std::lock_guard lock(m_mutex);
            m_snapshot = std::move(snap);
            m_doneTally = tally;
            m_doneChunk = chunk;
        }
        ++m_version;
        batch = std::min<uint64_t>(batch * 2, 16); // snapshots every few seconds at most
    }
    std::lock_guard lock(m_mutex);
    m_snapshot.pathsDone = tally.paths;
    m_snapshot.running = false;
}

SliceSnapshot SliceRunner::snapshot() const {
    std::lock_guard lock(m_mutex);
    return m_snapshot;
}

bool SliceStage::update(const SliceInputs& in) {
    if (!in.settings.enabled || !in.params) {
        if (!m_key.empty()) cancel();
        m_key.clear(); // shown again with the same inputs: the run resumes where it stopped
        return false;
    }
    bool changed = false;
    const int c = in.settings.channel;
    if (c < 0 || c > 2) {
        const std::string p =
            "slice: channel must be 0 (R), 1 (G) or 2 (B), got " + std::to_string(c);
        changed = p != m_problem;
        m_problem = p;
        return changed;
    }
    const pathtrace::Medium medium = mediaOf(*in.params)[size_t(c)];
    const pathtrace::EstimateSettings est = estimateSettings(in.settings, medium);
    // the device is part of the run: a change of it restarts on the other one
    const bool gpu = chooseGpu(in.settings.device, m_slabShader);
    const std::string key =
        core::keyOf(medium, est) + core::nameOf(in.settings.device) + (gpu ? ":gpu" : ":cpu");
    if (!m_problem.empty()) changed = true;
    m_problem.clear();
    if (key != m_key) {
        m_key = key;
        m_model = in.model;
        m_choice = in.settings.device == TracerDevice::Auto ? slabThroughput(m_slabShader).summary()
                                                            : std::string();
        if (gpu != m_gpuMode) cancel(); // the other device's run stops
        m_gpuMode = gpu;
        if (gpu)
            m_gpu.start(medium, est);
        else
            m_runner.start(medium, est);
        changed = true;
    }
    if (m_gpuMode) {
        changed |= m_gpu.step(8.0); // GL work is sliced per frame on this (the GL) thread
    } else if (const uint64_t v = m_runner.version(); v != m_seen) {
        m_seen = v;
        changed = true;
    }
    return evaluateModels(in) || changed;
}

bool SliceStage::evaluateModels(const SliceInputs& in) {
    if (!in.library || !in.views) return false;
    const int c = in.settings.channel;
    // the bins are the reference's (its medium's l_d), the σ each model's own
    const pathtrace::EstimateSettings est =
        estimateSettings(in.settings, mediaOf(*in.params)[size_t(c)]);
    try {
        pathtrace::validate(est);
    } catch (const core::Error&) {
        return false; // the reference names the bad setting; the models keep their last slices
    }
    bool changed = false;
    std::map<std::string, ModelSliceResult> next;
    for (const bssrdf::ModelEntry& e : in.library->entries()) {
        auto v = in.views->find(e.displayPath);
        if (!e.usable() || v == in.views->end() || !v->second.effective) continue;
        const material::MaterialParams& p = *v->second.effective;
        const pathtrace::Medium medium = mediaOf(p)[size_t(c)];
        const bool readsWo = !e.model->attrs.noWo;
        const std::string key =
            std::to_string(e.generation) + toJson(e.values).dump() +
            core::keyOf(builtinsOf(p), est.bins, c, in.settings.thetaIDeg, readsWo);
        ModelSliceResult& r = next[e.displayPath];
        if (auto old = m_models.find(e.displayPath);
            old != m_models.end() && old->second.key == key) {
            r = std::move(old->second);
            continue;
        }
        changed = true;
        r.key = key;
        r.medium = medium;
        try {
            const SliceSampling n = sliceSampling(est.bins, readsWo);
            const std::vector<bssrdf::Query> q =
                sliceQueries(est.bins, in.settings.thetaIDeg, readsWo, n);
            core::Stopwatch clock;
            const std::vector<glm::dvec3> rgb = bssrdf::evaluateQueries(
                e.programs.at("pencil_profile.comp").id(), *e.model, e.values, builtinsOf(p), q);
            std::vector<double> values(rgb.size());
            for (size_t i = 0; i < rgb.size(); ++i)
                values[i] = rgb[i][c];
            r.slice = modelSlice(est.bins, in.settings.thetaIDeg, medium.eta, readsWo, n, values);
            gl::recordTiming("slice: model " + (e.model ? e.model->name : e.displayPath),
                             clock.ms());
            r.problem.clear();
            for (double x : r.slice->R)
                if (!std::isfinite(x) || x < 0) {
                    r.problem = e.displayPath + ": Bssrdf() is negative or not finite on the slice";
                    break;
                }
        } catch (const core::Error& err) {
            r.slice.reset();
            r.problem = err.what();
        } catch (const std::exception& err) {
            r.slice.reset();
            r.problem = e.displayPath + ": " + err.what();
        }
    }
    changed |= next.size() != m_models.size(); // a model gone
    m_models = std::move(next);
    return changed;
}

StageStatus SliceStage::status() const {
    StageStatus st;
    const SliceSnapshot snap = snapshot();
    st.running = snap.running;
    st.progress = snap.pathsTarget ? double(snap.pathsDone) / double(snap.pathsTarget) : 1.0;
    if (!m_problem.empty()) st.problems.push_back(m_problem);
    if (!snap.problem.empty()) st.problems.push_back(snap.problem);
    if (!snap.energy.empty())
        st.problems.push_back("the estimate failed its own energy check: " + snap.energy);
    for (const auto& [path, r] : m_models)
        if (!r.problem.empty()) st.problems.push_back(r.problem);
    st.stats.emplace_back("paths/s", core::formatNumber(snap.pathsPerSecond, 3));
    st.stats.emplace_back("device", snap.device);
    if (!m_choice.empty()) st.stats.emplace_back("device choice", m_choice);
    return st;
}

shader::Records SliceStage::shaderRecords() const {
    shader::Records out;
    for (const auto& [name, record] : m_gpu.shaderRecords())
        out["slice:" + name] = record;
    return out;
}

SliceSnapshot SliceStage::finish(const SliceInputs& in) {
    SliceInputs on = in;
    on.settings.enabled = true;
    update(on);
    if (m_gpuMode) {
        while (m_gpu.step(1000.0)) {
        }
    } else {
        m_runner.wait();
    }
    update(on);
    return snapshot();
}

namespace {

// The model slice's per-value allowance for another driver (capture_entries.h): the slice made
// again from the model's values with its transcendental functions moved by the errors GLSL allows
// them (bssrdf/conditioning.h), twice the largest change of each bin's R and cell's S over the
// seeds; the geometry columns none. Without it (the perturbed program does not build) the replay
// keeps the floor alone, and the log says why.
void addSliceConditioning(const SliceInputs& in, const std::string& path, CaptureEntry& m) {
    const bssrdf::ModelEntry* e = nullptr;
    for (const bssrdf::ModelEntry& x : in.library->entries())
        if (x.displayPath == path) e = &x;
    const auto v = in.views->find(path);
    if (!e || !e->usable() || v == in.views->end() || !v->second.effective) return;
    const int c = in.settings.channel;
    const pathtrace::EstimateSettings est =
        estimateSettings(in.settings, mediaOf(*in.params)[size_t(c)]);
    const material::MaterialParams& p = *v->second.effective;
    const bool readsWo = !e->model->attrs.noWo;
    try {
        const SliceSampling n = sliceSampling(est.bins, readsWo);
        const auto evals =
            bssrdf::perturbedQueries(*e->model, in.library->sources(), e->values, builtinsOf(p),
                                     sliceQueries(est.bins, in.settings.thetaIDeg, readsWo, n));
        std::vector<ModelSlice> slices;
        for (const std::vector<glm::dvec3>& rgb : evals) {
            std::vector<double> values(rgb.size());
            for (size_t i = 0; i < rgb.size(); ++i)
                values[i] = rgb[i][c];
            slices.push_back(modelSlice(est.bins, in.settings.thetaIDeg, mediaOf(p)[size_t(c)].eta,
                                        readsWo, n, values));
        }
        const size_t geometry = 5, bins = slices[0].R.size();
        const size_t cells = m.table.columns.size() - geometry - 1;
        if (m.table.rows.size() != bins) return;
        const auto spread = [&](auto member, size_t i) {
            double d = 0;
            for (size_t k = 1; k < slices.size(); ++k) {
                const double x = std::fabs((slices[k].*member)[i] - (slices[0].*member)[i]);
                if (std::isfinite(x)) d = std::max(d, x);
            }
            return 2 * d;
        };
        m.conditioning.columns = m.table.columns;
        for (size_t bin = 0; bin < bins; ++bin) {
            std::vector<double> row(geometry, 0.0);
            row.push_back(spread(&ModelSlice::R, bin));
            for (size_t k = 0; k < cells; ++k)
                row.push_back(spread(&ModelSlice::S, bin * cells + k));
            m.conditioning.rows.push_back(std::move(row));
        }
        m.conditioningNote = "2x the spread of each value under the errors GLSL 4.50 allows the "
                             "model's exp, log, pow and sqrt (" +
                             std::to_string(bssrdf::kConditioningPatterns) + " sign patterns)";
    } catch (const core::Error& err) {
        core::logInfo(path + ": no per-value slice tolerance for another driver (" + err.what() +
                      "); the replay allows the relative floor alone");
    }
}

} // namespace

void SliceStage::capture(const SliceInputs& in, CaptureEntries& out) {
    if (!in.settings.enabled) return;
    const SliceSnapshot snap = finish(in);
    if (!snap.problem.empty()) throw core::Error("slice", 0, snap.problem);
    if (!snap.slice) return;
    out.resolved.push_back({"slice", "device", m_gpuMode ? "gpu" : "cpu"});
    const pathtrace::BssrdfBins& b = snap.settings.bins;
    const pathtrace::BssrdfSlice& s = *snap.slice;
    const std::vector<double> edges = b.rEdges();
    const size_t cells = b.dirBins() > 1 ? size_t(b.dirBins()) : 0;
    auto geometry = [&](size_t bin) {
        const int ir = int(bin) / b.thetaSBins, it = int(bin) % b.thetaSBins;
        const double dth = 180.0 / b.thetaSBins;
        return std::vector<double>{double(bin), edges[size_t(ir)], edges[size_t(ir) + 1], it * dth,
                                   (it + 1) * dth};
    };
    const std::vector<std::string> geomColumns{"bin", "r_lo_mm", "r_hi_mm", "theta_s_lo_deg",
                                               "theta_s_hi_deg"};
    CaptureEntry ref = captureEntry(CaptureEntry::Kind::CsvStat, "slice", "bin");
    ref.alpha = kMonteCarloAlpha;
    ref.note = "Monte Carlo: per-value z-test, Bonferroni over all bins and cells";
    ref.table.comments = {"BSSRDF slice (seed 001), sigma of " + m_model + ", channel " +
                              std::string(1, "RGB"[std::clamp(in.settings.channel, 0, 2)]) +
                              ", theta_i " + core::formatNumber(s.thetaIDeg, 6) + " deg, " +
                              std::to_string(snap.pathsDone) + " paths",
                          "R per incident photon (MCML), 1/mm^2; S_k in exit cell k, 1/(mm^2 sr)",
                          "last row (bin -1): total diffuse reflectance"};
    ref.table.columns = geomColumns;
    ref.table.columns.insert(ref.table.columns.end(), {"R", "R_stderr"});
    for (size_t k = 0; k < cells; ++k) {
        ref.table.columns.push_back("S" + std::to_string(k));
        ref.table.columns.push_back("S" + std::to_string(k) + "_stderr");
    }
    for (size_t bin = 0; bin < s.R.size(); ++bin) {
        std::vector<double> row = geometry(bin);
        row.insert(row.end(), {s.R[bin], s.RStderr[bin]});
        for (size_t k = 0; k < cells; ++k)
            row.insert(row.end(), {s.S[bin * cells + k], s.SStderr[bin * cells + k]});
        ref.table.rows.push_back(std::move(row));
    }
    std::vector<double> total{-1, 0, 0, 0, 0, s.totalRd, s.totalRdStderr};
    total.resize(ref.table.columns.size(), 0.0);
    ref.table.rows.push_back(std::move(total));
    out.entries.push_back(std::move(ref));
    for (const auto& [path, r] : m_models) {
        if (!r.slice) continue;
        const std::string name = std::filesystem::path(path).stem().string();
        CaptureEntry m = captureEntry(CaptureEntry::Kind::Csv, "slice_model." + name, "bin");
        m.relTol = kProfileRelTol;
        m.note = "float32 GPU evaluation of Bssrdf(), averaged in double";
        m.table.comments = {"model " + path + " on the slice's bins, own sigma",
                            "R per incident photon, 1/mm^2; S_k in exit cell k, 1/(mm^2 sr)"};
        m.table.columns = geomColumns;
        m.table.columns.push_back("R");
        for (size_t k = 0; k < cells; ++k)
            m.table.columns.push_back("S" + std::to_string(k));
        for (size_t bin = 0; bin < r.slice->R.size(); ++bin) {
            std::vector<double> row = geometry(bin);
            row.push_back(r.slice->R[bin]);
            for (size_t k = 0; k < cells; ++k)
                row.push_back(r.slice->S[bin * cells + k]);
            m.table.rows.push_back(std::move(row));
        }
        if (out.forReplay) addSliceConditioning(in, path, m);
        out.entries.push_back(std::move(m));
    }
}

} // namespace app
