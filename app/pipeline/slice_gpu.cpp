// The BSSRDF slice on the GL compute walk (slice_gpu.h).
#include "pipeline/slice_gpu.h"

#include "core/core.h"

#include <algorithm>

namespace app {

void GpuSliceRunner::start(const pathtrace::Medium& m, const pathtrace::EstimateSettings& s) {
    m_problem.clear();
    m_target = 0;
    m_seconds = 0;
    try {
        pathtrace::validate(m, "slice medium");
        pathtrace::validate(s);
        if (s.thetaIDeg.size() != 1) throw core::Error("slice", 0, "one incidence angle at a time");
        if (!m_gpu) m_gpu = std::make_unique<pathtrace::GpuBssrdfEstimator>(m_shaderFile);
        m_gpu->reset(m, s, 0);
    } catch (const core::Error& e) {
        m_problem = e.what(); // the last table stays
        m_snap.problem = m_problem;
        m_snap.running = false;
        return;
    }
    m_medium = m;
    m_settings = s;
    m_settings.splitting.levels = 0; // what the GL walk traces
    m_settings.exits.samples = 0;
    m_target = s.paths;
    SliceSnapshot fresh;
    fresh.device = "GPU";
    fresh.medium = m;
    fresh.settings = m_settings;
    fresh.settings.paths = 0;
    fresh.pathsTarget = m_target;
    fresh.running = true;
    fresh.problem = m_shaderProblem;
    m_snap = std::move(fresh);
}

bool GpuSliceRunner::running() const {
    return m_gpu && m_problem.empty() && m_gpu->pathsDone() < m_target;
}

bool GpuSliceRunner::step(double budgetMs) {
    if (!running()) return false;
    core::Stopwatch clock;
    try {
        while (running() && clock.ms() < budgetMs) {
            core::Stopwatch one;
            m_gpu->step(std::min(m_perStep, m_target - m_gpu->pathsDone()));
            // steps of about a quarter of the budget: a frame overshoots it by at most that
            const double ms = std::max(one.ms(), 1e-3);
            const double want = double(m_perStep) * 0.25 * budgetMs / ms;
            m_perStep = uint64_t(std::clamp(want, 64.0, double(uint64_t(1) << 20)));
        }
    } catch (const core::Error& e) {
        m_problem = e.what(); // an impossible tally from an edited shader: the run stops
    }
    m_seconds += clock.ms() * 1e-3;
    publish();
    return true;
}

void GpuSliceRunner::publish() {
    const uint64_t done = m_gpu ? m_gpu->pathsDone() : 0;
    m_snap.running = running();
    m_snap.pathsDone = done;
    m_snap.pathsTarget = m_target;
    m_snap.pathsPerSecond = m_seconds > 0 ? double(done) / m_seconds : 0;
    m_snap.problem = m_problem.empty() ? m_shaderProblem : m_problem;
    if (done == 0) return;
    m_snap.settings = m_settings;
    m_snap.settings.paths = done;
    m_snap.slice =
        pathtrace::finalize(m_gpu->tally(), m_settings.bins, m_settings.thetaIDeg[0], m_medium);
    m_snap.energy = pathtrace::energyProblem(*m_snap.slice, m_settings.orders);
}

void GpuSliceRunner::cancel() {
    if (m_gpu) m_target = std::min(m_target, m_gpu->pathsDone());
    m_snap.running = false;
}

bool GpuSliceRunner::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    if (!m_gpu || !m_gpu->shaderRecord().dependencies.containsAny(changed)) return false;
    try {
        m_gpu->reload(); // a successful build starts the tally over
        m_shaderProblem.clear();
        if (!m_settings.thetaIDeg.empty()) start(m_medium, m_settings); // the run, from path 0
    } catch (const core::Error& e) {
        m_shaderProblem = e.what();
        core::logError("slice walk shader: " + m_shaderProblem + " (previous program kept)");
    }
    m_snap.problem = m_problem.empty() ? m_shaderProblem : m_problem;
    return true;
}

shader::Records GpuSliceRunner::shaderRecords() const {
    shader::Records out;
    if (m_gpu) out[m_shaderFile.filename().string()] = m_gpu->shaderRecord();
    return out;
}

} // namespace app
