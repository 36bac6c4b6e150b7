// The geometry stage (geometry_stage.h).
#include "pipeline/geometry_stage.h"

#include "core/core.h"
#include "core/fields.h"
#include "integrate/integrate.h"
#include "pipeline/param_json.h"

#include <algorithm>
#include <cmath>

namespace app {

struct GeometryStage::Work {
    size_t cell = 0;
    std::string key;
    std::unique_ptr<integrate::ImageIntegrator> integrator;
};

namespace {

std::string modelKey(const bssrdf::ModelEntry& e) {
    return std::to_string(e.generation) + toJson(e.values).dump();
}

std::string stemOf(const std::string& displayPath) {
    std::string m = displayPath.substr(displayPath.rfind('/') + 1);
    return m.substr(0, m.rfind('.'));
}

} // namespace

GeometryStage::GeometryStage() = default;

GeometryStage::~GeometryStage() {
    stopWorker();
}

void GeometryStage::stopWorker() {
    m_cancel = true;
    if (m_worker.joinable()) m_worker.join();
    m_cancel = false;
}

void GeometryStage::cancel() {
    stopWorker();
    m_work.reset();
    m_key.clear(); // the next run starts over (its references from the disk cache)
}

void GeometryStage::restart(const GeometryInputs& in, const std::string& key) {
    stopWorker();
    m_work.reset();
    m_key = key;
    m_problems.clear();
    m_workerProblem.clear();
    m_cells.clear();
    m_models.clear();
    m_settings = in.request->settings;
    m_shapes.clear();
    m_cases.clear();
    m_refs.clear();
    m_ldMm = 0;
    try {
        std::vector<GeometrySkip> skipped;
        const std::vector<GeometryCase> all =
            geometryCases(*in.presets, in.request->shapes, {in.request->preset}, &skipped);
        for (const GeometryCase& c : all)
            if (c.channel == in.request->channel) m_cases.push_back(c);
        for (const GeometrySkip& s : skipped)
            if (s.channel == in.request->channel)
                m_problems.push_back(s.preset + " " + std::string(1, "RGB"[s.channel]) + ": " +
                                     s.reason);
    } catch (const core::Error& e) {
        m_problems.push_back(e.what());
        m_cases.clear();
    }
    for (const GeometryCase& c : m_cases)
        m_shapes.push_back(c.shape);
    if (!m_cases.empty()) m_ldMm = m_cases.front().ldMm;
    m_refs.assign(m_cases.size(), std::nullopt);
    m_refDone = 0;
    m_refTotal = std::max<uint64_t>(1, 1000 * m_cases.size());
    m_workerDone = false;
    m_worker = std::thread([this, cases = m_cases, settings = m_settings] {
        for (size_t k = 0; k < cases.size() && !m_cancel; ++k) {
            try {
                bool fromCache = false;
                auto ref = geometryReference(
                    cases[k], settings,
                    [&](uint64_t done, uint64_t total) {
                        m_refDone = 1000 * k + (total ? 1000 * done / total : 1000);
                    },
                    &m_cancel, fromCache);
                std::lock_guard lock(m_mutex);
                m_refs[k] = std::move(ref);
            } catch (const core::Error& e) {
                std::lock_guard lock(m_mutex);
                m_workerProblem = e.what();
                break;
            }
            m_refDone = 1000 * (k + 1);
        }
        m_workerDone = true;
    });
}

const GeometryCell* GeometryStage::cell(const std::string& displayPath,
                                        const std::string& shape) const {
    for (const GeometryCell& c : m_cells)
        if (c.displayPath == displayPath && c.shape == shape) return &c;
    return nullptr;
}

const ChannelImage* GeometryStage::reference(const std::string& shape) const {
    std::lock_guard lock(m_mutex);
    for (size_t k = 0; k < m_shapes.size(); ++k)
        if (m_shapes[k] == shape && m_refs[k]) return &*m_refs[k];
    return nullptr;
}

void GeometryStage::rank() {
    std::vector<GeometryRow> rows;
    std::vector<size_t> of;
    for (size_t i = 0; i < m_cells.size(); ++i) {
        const GeometryCell& c = m_cells[i];
        if (!c.image || !c.score.problem.empty()) continue;
        rows.push_back({c.model, c.shape, "", "", 0, 0, c.score, 0, false});
        of.push_back(i);
    }
    rankGeometryRows(rows);
    for (GeometryCell& c : m_cells)
        c.rank = 0, c.tie = false;
    for (size_t r = 0; r < rows.size(); ++r) {
        m_cells[of[r]].rank = rows[r].rank;
        m_cells[of[r]].tie = rows[r].tie;
    }
}

bool GeometryStage::update(const GeometryInputs& in) {
    if (!in.request || !in.library || !in.presets) return false;
    if (!in.request->enabled) {
        if (m_worker.joinable() || m_work) cancel();
        return false;
    }
    const std::string key = core::keyOf(in.request->preset, in.request->channel, in.request->shapes,
                                        in.request->settings);
    if (key != m_key) {
        restart(in, key);
        return true;
    }
    if (m_workerDone && m_worker.joinable()) m_worker.join();
    // the models: cells for every usable model and shape, kept across model edits
    std::vector<std::string> models;
    for (const auto& e : in.library->entries())
        if (e.usable()) models.push_back(e.displayPath);
    if (models != m_models) {
        std::vector<GeometryCell> cells;
        for (const std::string& shape : m_shapes)
            for (const std::string& m : models) {
                const GeometryCell* old = cell(m, shape);
                cells.push_back(old ? *old
                                    : GeometryCell{stemOf(m), m, shape, {}, {}, 0, false, ""});
            }
        m_cells = std::move(cells);
        m_models = models;
        m_work.reset();
    }
    bool changed = false;
    core::Stopwatch clock;
    for (int steps = 0; steps == 0 || clock.ms() < frameBudgetMs; ++steps) {
        if (!m_work) { // the next cell whose image is missing or made with an older model
            for (size_t i = 0; i < m_cells.size() && !m_work; ++i) {
                GeometryCell& c = m_cells[i];
                const bssrdf::ModelEntry* e = in.library->find(c.displayPath);
                if (!e || !e->usable() || c.key == modelKey(*e)) continue;
                const size_t k = i / std::max<size_t>(1, m_models.size());
                {
                    std::lock_guard lock(m_mutex);
                    if (!m_refs[k]) continue;
                }
                auto w = std::make_unique<Work>();
                w->cell = i;
                w->key = modelKey(*e);
                try {
                    w->integrator = geometryIntegrator(
                        *e, geometryMaterial(*in.presets, m_cases[k]), m_cases[k], m_settings);
                    m_work = std::move(w);
                } catch (const core::Error& err) { // said in the cell and in Errors
                    c.key = w->key;
                    c.image.reset();
                    c.score = {};
                    c.score.problem = err.what();
                    changed = true;
                }
            }
            if (!m_work) break;
        }
        Work& w = *m_work;
        w.integrator->step(1);
        if (w.integrator->samplesPerPixelDone() < m_settings.modelSpp) continue;
        GeometryCell& c = m_cells[w.cell];
        const size_t k = w.cell / m_models.size();
        c.key = w.key;
        c.score = {};
        try {
            c.image = geometryChannelImage(*w.integrator, m_cases[k], c.displayPath);
            std::lock_guard lock(m_mutex);
            c.score = imageRelativeL2(*c.image, *m_refs[k]);
        } catch (const core::Error& err) {
            c.image.reset();
            c.score.problem = err.what();
        }
        m_work.reset();
        rank();
        changed = true;
    }
    return changed;
}

StageStatus GeometryStage::status() const {
    StageStatus s;
    size_t done = 0;
    for (const GeometryCell& c : m_cells)
        done += !c.key.empty();
    const double refs = double(m_refDone.load()) / double(m_refTotal.load());
    const double cells = m_cells.empty() ? 0.0 : double(done) / double(m_cells.size());
    s.running = !m_key.empty() && (!m_workerDone || m_work || done < m_cells.size()) &&
                m_workerProblem.empty();
    s.progress = 0.5 * (refs + cells);
    s.problems = m_problems;
    for (const GeometryCell& c : m_cells)
        if (!c.score.problem.empty())
            s.problems.push_back(c.model + " on " + c.shape + ": " + c.score.problem);
    {
        std::lock_guard lock(m_mutex);
        if (!m_workerProblem.empty()) s.problems.push_back(m_workerProblem);
    }
    s.stats.emplace_back("images", std::to_string(done) + " / " + std::to_string(m_cells.size()));
    s.stats.emplace_back("references", core::formatNumber(100 * refs, 3) + " %");
    return s;
}

} // namespace app
