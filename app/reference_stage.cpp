// Background progressive path tracing for the pencil-plot reference curve.
#include "reference_stage.h"

#include "core/core.h"

#include <algorithm>

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

ReferenceSnapshot ReferenceRunner::snapshot() const {
    std::lock_guard lock(m_mutex);
    return m_snapshot;
}

} // namespace app
