// gl stage timing: CPU stopwatch + GL_TIME_ELAPSED queries, results collected lazily so the
// frame never stalls on the GPU.
#include "gl.h"

#include "core/core.h"

#include <map>
#include <mutex>

namespace gl {
namespace {
struct Pending {
    std::string stage;
    GLuint query;
};
std::mutex g_mutex;
std::map<std::string, StageTiming> g_table;
std::vector<Pending> g_pending;
} // namespace

// GL_TIME_ELAPSED queries cannot nest: a timer opened inside another one measures CPU time
// only (its GPU time is part of the enclosing stage's).
thread_local int t_openQueries = 0;

ScopedStageTimer::ScopedStageTimer(std::string stage)
    : m_stage(std::move(stage)), m_startMs(core::secondsSinceStart() * 1000.0) {
    if (t_openQueries++ > 0) return;
    glGenQueries(1, &m_query);
    glBeginQuery(GL_TIME_ELAPSED, m_query);
}

ScopedStageTimer::~ScopedStageTimer() {
    --t_openQueries;
    if (m_query) glEndQuery(GL_TIME_ELAPSED);
    const double cpu = core::secondsSinceStart() * 1000.0 - m_startMs;
    std::lock_guard lock(g_mutex);
    auto& t = g_table[m_stage];
    t.stage = m_stage;
    t.cpuMs = cpu;
    ++t.runs;
    if (m_query) g_pending.push_back({m_stage, m_query});
}

void collectTimings(bool wait) {
    std::lock_guard lock(g_mutex);
    for (auto it = g_pending.begin(); it != g_pending.end();) {
        GLint available = 0;
        if (wait) glFinish();
        glGetQueryObjectiv(it->query, GL_QUERY_RESULT_AVAILABLE, &available);
        if (!available) {
            ++it;
            continue;
        }
        GLuint64 ns = 0;
        glGetQueryObjectui64v(it->query, GL_QUERY_RESULT, &ns);
        // Exactly 0 ns is no measurement (software drivers run the work outside the query),
        // not a stage that took no time.
        auto& t = g_table[it->stage];
        t.gpuUnmeasurable = ns == 0;
        t.gpuMs = ns == 0 ? -1.0 : static_cast<double>(ns) * 1e-6;
        glDeleteQueries(1, &it->query);
        it = g_pending.erase(it);
    }
}

std::vector<StageTiming> timings() {
    std::lock_guard lock(g_mutex);
    std::vector<StageTiming> out;
    for (auto& [k, v] : g_table)
        out.push_back(v);
    return out;
}

void recordTiming(const std::string& stage, double cpuMs) {
    std::lock_guard lock(g_mutex);
    auto& t = g_table[stage];
    t.stage = stage;
    t.cpuMs = cpuMs;
    ++t.runs;
}

} // namespace gl
