// Background progressive path tracing for the pencil-plot reference curve.
#include "pipeline/reference_stage.h"

#include "core/core.h"

#include "core/fields.h"

#include <algorithm>
#include <string>

namespace app {

ReferenceRunner::~ReferenceRunner() {
    cancel();
}

void ReferenceRunner::cancel() {
    m_cancel = true;
    if (m_thread.joinable()) m_thread.join();
    m_cancel = false;
    std::lock_guard lock(m_mutex);
    m_snapshot.running = false;
}

void ReferenceRunner::start(const std::array<pathtrace::Medium, 3>& media,
                            const pathtrace::SlabSettings& s, uint64_t pathsPerChannel) {
    cancel();
    {
        std::lock_guard lock(m_mutex);
        m_snapshot = ReferenceSnapshot{};
        m_snapshot.pathsTarget = pathsPerChannel;
        try {
            const char* names[3] = {"reference (R)", "reference (G)", "reference (B)"};
            for (int c = 0; c < 3; ++c)
                pathtrace::validate(media[c], names[c]);
            pathtrace::SlabSettings check = s;
            check.paths = pathsPerChannel;
            pathtrace::validate(check);
        } catch (const core::Error& e) {
            m_snapshot.problem = e.what();
            ++m_version;
            return;
        }
        m_snapshot.running = true;
    }
    ++m_version;
    m_thread = std::thread(&ReferenceRunner::run, this, media, s, pathsPerChannel);
}

void ReferenceRunner::run(std::array<pathtrace::Medium, 3> media, pathtrace::SlabSettings s,
                          uint64_t target) {
    std::array<pathtrace::SlabTally, 3> tally;
    std::array<pathtrace::SlabSettings, 3> settings;
    for (int c = 0; c < 3; ++c) {
        settings[c] = s;
        settings[c].seed = s.seed * 3 + uint64_t(c); // independent channels
    }
    core::Stopwatch clock;
    uint64_t done = 0, batch = 4096;
    while (done < target && !m_cancel) {
        const uint64_t n = std::min(batch, target - done);
        for (int c = 0; c < 3 && !m_cancel; ++c)
            tally[c].merge(pathtrace::traceSlab(media[c], settings[c], done, n, &m_cancel));
        if (m_cancel) break; // the partial batch is dropped: the snapshot stays a prefix
        done += n;
        ReferenceSnapshot snap;
        snap.running = done < target;
        snap.pathsDone = done;
        snap.pathsTarget = target;
        snap.pathsPerSecond = 3.0 * double(done) / std::max(1e-9, clock.ms() * 1e-3);
        for (int c = 0; c < 3; ++c) {
            settings[c].paths = done;
            snap.channel[c] = pathtrace::finalize(tally[c], settings[c]);
        }
        {
            std::lock_guard lock(m_mutex);
            m_snapshot = std::move(snap);
        }
        ++m_version;
        // grow batches so snapshots arrive every ~100 ms without dominating the work
        batch = std::min<uint64_t>(batch * 2, 262144);
    }
}

void ReferenceRunner::wait() {
    if (m_thread.joinable()) m_thread.join();
}

void checkEnergy(ReferenceSnapshot& snap) {
    snap.energy.clear();
    for (int c = 0; c < 3; ++c) {
        const std::string p = pathtrace::energyProblem(snap.channel[c]);
        snap.energyFailed[size_t(c)] = !p.empty();
        if (p.empty()) continue;
        if (!snap.energy.empty()) snap.energy += "; ";
        snap.energy += std::string("channel ") + "RGB"[c] + ": " + p;
    }
}

ReferenceSnapshot ReferenceRunner::snapshot() const {
    std::lock_guard lock(m_mutex);
    ReferenceSnapshot snap = m_snapshot;
    checkEnergy(snap);
    return snap;
}

void GpuReference::start(const std::array<pathtrace::Medium, 3>& media,
                         const pathtrace::SlabSettings& s, uint64_t pathsPerChannel) {
    m_problem.clear();
    m_done = m_target = 0;
    m_seconds = 0;
    m_media = media;
    try {
        for (int c = 0; c < 3; ++c) {
            m_settings[c] = s;
            m_settings[c].paths = pathsPerChannel;
            m_settings[c].seed = s.seed * 3 + uint64_t(c); // independent channels
            if (!m_tracers[c])
                m_tracers[c] = std::make_unique<pathtrace::GpuSlabTracer>(m_shaderFile);
            m_tracers[c]->reset(media[c], m_settings[c]);
        }
        m_target = pathsPerChannel;
    } catch (const core::Error& e) {
        m_problem = e.what();
    }
}

bool GpuReference::step(double budgetMs) {
    if (m_done >= m_target || !m_problem.empty()) return false;
    core::Stopwatch clock;
    const uint64_t before = m_done;
    try {
        // a few thousand paths per channel per slice keep a frame near its budget on llvmpipe
        while (m_done < m_target && clock.ms() < budgetMs) {
            const uint64_t n = std::min<uint64_t>(4096, m_target - m_done);
            for (int c = 0; c < 3; ++c)
                m_tracers[c]->step(n);
            m_done = m_tracers[0]->pathsDone();
        }
    } catch (const core::Error& e) {
        m_problem = e.what();
    }
    m_seconds += clock.ms() * 1e-3;
    return m_done != before;
}

void GpuReference::reload() {
    try {
        for (auto& t : m_tracers)
            if (t) t->reload();
        m_shaderProblem.clear();
        // a successful reload starts the tallies over (with the channel-0 seed base)
        pathtrace::SlabSettings base = m_settings[0];
        base.seed /= 3;
        if (m_target > 0) start(m_media, base, m_target);
    } catch (const core::Error& e) {
        m_shaderProblem = e.what();
        core::logError("path tracer shader: " + m_shaderProblem + " (previous program kept)");
    }
}

bool GpuReference::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    for (const auto& t : m_tracers)
        if (t && t->shaderRecord().dependencies.containsAny(changed)) {
            reload();
            return true;
        }
    return false;
}

shader::Records GpuReference::shaderRecords() const {
    shader::Records out;
    for (int c = 0; c < 3; ++c)
        if (m_tracers[c])
            out[m_shaderFile.filename().string() + "[" + "RGB"[c] + "]"] =
                m_tracers[c]->shaderRecord();
    return out;
}

ReferenceSnapshot GpuReference::snapshot() const {
    ReferenceSnapshot snap;
    snap.problem = m_problem.empty() ? m_shaderProblem : m_problem;
    snap.pathsDone = m_done;
    snap.pathsTarget = m_target;
    snap.running = m_done < m_target && m_problem.empty();
    snap.device = "GPU";
    snap.pathsPerSecond = m_seconds > 0 ? 3.0 * double(m_done) / m_seconds : 0;
    if (m_done == 0) return snap;
    for (int c = 0; c < 3; ++c) {
        pathtrace::SlabSettings s = m_settings[c];
        s.paths = m_done;
        snap.channel[c] = pathtrace::finalize(m_tracers[c]->tally(), s);
    }
    checkEnergy(snap);
    return snap;
}

std::array<pathtrace::Medium, 3> mediaOf(const material::MaterialParams& p) {
    std::array<pathtrace::Medium, 3> media;
    for (int c = 0; c < 3; ++c)
        media[c] = {p.sigmaA[c], p.sigmaS[c], p.g, p.eta};
    return media;
}

bool ReferenceStage::update(const ReferenceInputs& in) {
    if (!in.settings.enabled) {
        if (!m_key.empty()) cancel();
        m_key.clear();
        return false;
    }
    // GPU work is sliced per frame on this (the GL) thread
    if (m_gpuMode && m_gpu.step(8.0)) ++m_gpuSteps;
    if (in.params) {
        const material::MaterialParams& p = *in.params;
        pathtrace::SlabSettings s;
        s.rMaxMm = in.rMaxMm;
        s.bins = in.settings.bins;
        s.seed = in.settings.seed;
        s.estimator = in.settings.estimator;
        s.exits.samples = in.settings.exitSamples;
        material::MaterialParams keyed = p;
        keyed.scale = 0; // lengths of the slab are in mm: the mesh scale is no input
        const std::string key = core::keyOf(keyed, in.rMaxMm, in.settings);
        if (key != m_key) {
            m_key = key;
            m_model = in.model;
            cancel();
            // connections are CPU only: auto keeps them there, gpu names the problem
            const ReferenceSettings& rs = in.settings;
            m_gpuMode = rs.device == TracerDevice::Gpu ||
                        (rs.device == TracerDevice::Auto &&
                         rs.estimator != pathtrace::Estimator::Connections &&
                         chooseGpu(rs.device, m_gpu.shaderFile()));
            m_auto = rs.device == TracerDevice::Auto;
            if (m_auto)
                m_choice = rs.estimator == pathtrace::Estimator::Connections
                               ? std::string("CPU (connections run on the CPU only)")
                               : slabThroughput(m_gpu.shaderFile()).summary();
            if (m_gpuMode)
                m_gpu.start(mediaOf(p), s, in.settings.paths);
            else
                m_cpu.start(mediaOf(p), s, in.settings.paths);
        }
    }
    const uint64_t seen = m_cpu.version() + m_gpuSteps;
    if (seen == m_seen) return false;
    m_seen = seen;
    return true;
}

void ReferenceStage::cancel() {
    m_cpu.cancel();
    m_gpu.cancel();
}

ReferenceSnapshot ReferenceStage::finish(const ReferenceInputs& in) {
    update(in);
    if (m_gpuMode) {
        while (m_gpu.step(1000.0)) {
        }
    } else {
        m_cpu.wait();
    }
    return snapshot();
}

StageStatus ReferenceStage::status() const {
    StageStatus st;
    if (m_key.empty()) return st;
    const ReferenceSnapshot snap = snapshot();
    st.running = snap.running;
    st.progress = snap.pathsTarget ? double(snap.pathsDone) / double(snap.pathsTarget) : 1.0;
    if (!snap.problem.empty()) st.problems.push_back(snap.problem);
    if (!snap.energy.empty()) st.problems.push_back(snap.energy);
    st.stats.push_back({"paths per channel", std::to_string(snap.pathsDone)});
    st.stats.push_back({"device", snap.device});
    if (m_auto) st.stats.push_back({"device choice", m_choice});
    return st;
}

shader::Records ReferenceStage::shaderRecords() const {
    shader::Records out;
    for (const auto& [name, record] : m_gpu.shaderRecords())
        out["reference:" + name] = record;
    return out;
}

void ReferenceStage::capture(const ReferenceInputs& in, CaptureEntries& out) {
    if (!in.settings.enabled) return;
    const ReferenceSnapshot snap = finish(in);
    if (!snap.problem.empty()) throw core::Error("reference", 0, snap.problem);
    if (snap.pathsDone == 0) return;
    out.resolved.push_back({"reference", "device", m_gpuMode ? "gpu" : "cpu"});
    CaptureEntry e = captureEntry(CaptureEntry::Kind::CsvStat, "reference", "r_mm");
    e.alpha = kMonteCarloAlpha;
    e.note = "Monte Carlo: per-value z-test, Bonferroni over all bins and channels";
    capture::Table& t = e.table;
    t.comments = {"path-traced reference, sigma of " + m_model,
                  "R_d per unit area per incident photon (MCML convention), 1/mm^2",
                  "paths per channel " + std::to_string(snap.pathsDone),
                  "last row (r_mm = -1): total diffuse reflectance per channel"};
    t.columns = {"r_mm", "R", "R_stderr", "G", "G_stderr", "B", "B_stderr"};
    for (size_t i = 0; i < snap.channel[0].rMid.size(); ++i) {
        std::vector<double> row{snap.channel[0].rMid[i]};
        for (int c = 0; c < 3; ++c) {
            row.push_back(snap.channel[c].rd[i]);
            row.push_back(snap.channel[c].rdStderr[i]);
        }
        t.rows.push_back(std::move(row));
    }
    std::vector<double> totals{-1};
    for (int c = 0; c < 3; ++c) {
        totals.push_back(snap.channel[c].totalRd);
        totals.push_back(snap.channel[c].totalRdStderr);
    }
    t.rows.push_back(std::move(totals));
    out.entries.push_back(std::move(e));
}

} // namespace app
