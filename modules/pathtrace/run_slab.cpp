// pathtrace/run_slab: multi-threaded slab runs with results independent of the thread count.
//   Paths are cut into chunks of kChunkPaths (independent of the thread count). Worker
//   threads (std::thread) take chunks in increasing order from an atomic counter and trace each
//   into a ring slot of per-path records; the calling thread adds the records into the tally
//   path by path, in chunk order, so every sum is formed in exactly the order of a
//   single-threaded traceSlab(m, s, 0, paths): bitwise identical for any thread count. The ring
//   (2 slots per worker) bounds memory; a worker waits for its slot to be merged. The calling
//   thread polls every 50 ms: it merges, reports progress and watches `cancel`; on cancel the
//   workers stop (checked every 256 paths) and the result keeps the completed prefix of chunks.
#include "core/core.h"
#include "pathtrace/detail/slab_chunk.h"
#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace pathtrace {
namespace {

struct Slot {
    std::vector<PathRecord> records;
    uint64_t chunk = 0;
    uint64_t count = 0;
    bool ready = false;    // traced and waiting to be merged
    bool complete = false; // all `count` paths traced (not cut short by cancel)
};

class ChunkRunner {
  public:
    ChunkRunner(const Medium& m, const SlabSettings& s, int workers)
        : m_medium(m), m_settings(s), m_chunks((s.paths + kChunkPaths - 1) / kChunkPaths),
          m_slots(static_cast<size_t>(2 * workers)) {
        for (auto& slot : m_slots)
            slot.records.resize(static_cast<size_t>(std::min<uint64_t>(kChunkPaths, s.paths)));
    }

    // Worker loop: trace chunks in increasing order until none are left or the run is aborted.
    void work() {
        for (;;) {
            const uint64_t c = m_next.fetch_add(1);
            if (c >= m_chunks || aborted()) return;
            Slot& slot = m_slots[c % m_slots.size()];
            {
                std::unique_lock lock(m_mutex);
                m_cv.wait(lock, [&] { return c < m_merged + m_slots.size() || aborted(); });
                if (aborted()) return;
            }
            const uint64_t first = c * kChunkPaths;
            const uint64_t count = std::min(kChunkPaths, m_settings.paths - first);
            const uint64_t got = detail::traceChunk(m_medium, m_settings, first, count,
                                                    slot.records.data(), &m_abort);
            {
                std::lock_guard lock(m_mutex);
                slot.chunk = c;
                slot.count = got;
                slot.complete = got == count;
                slot.ready = true;
                m_traced += got;
                ++m_reports;
            }
            m_cv.notify_all();
            if (got < count) return; // aborted
        }
    }

    // Merges the chunks that are ready, in chunk order, into `t`.
    void mergeReady(SlabTally& t) {
        for (;;) {
            Slot* slot = nullptr;
            {
                std::lock_guard lock(m_mutex);
                if (m_merged >= m_chunks || m_broken) return;
                Slot& s = m_slots[m_merged % m_slots.size()];
                if (!s.ready || s.chunk != m_merged) return;
                if (!s.complete) {
                    m_broken = true; // a cut-short chunk ends the prefix
                    return;
                }
                slot = &s;
            }
            for (uint64_t i = 0; i < slot->count; ++i) // the slot is ours until marked free
                accumulate(t, slot->records[i], m_settings);
            {
                std::lock_guard lock(m_mutex);
                slot->ready = false;
                ++m_merged;
            }
            m_cv.notify_all();
        }
    }

    bool finished() {
        std::lock_guard lock(m_mutex);
        return m_merged >= m_chunks || m_broken;
    }
    uint64_t traced() {
        std::lock_guard lock(m_mutex);
        return m_traced;
    }
    bool aborted() const { return m_abort.load(std::memory_order_relaxed); }
    void abort() {
        {
            std::lock_guard lock(m_mutex);
            m_abort.store(true);
        }
        m_cv.notify_all();
    }
    // Waits until a worker reports a chunk or `timeout` passes.
    void waitForChunk(uint64_t& seen, std::chrono::milliseconds timeout) {
        std::unique_lock lock(m_mutex);
        m_cv.wait_for(lock, timeout, [&] { return m_reports != seen; });
        seen = m_reports;
    }

  private:
    const Medium& m_medium;
    const SlabSettings& m_settings;
    const uint64_t m_chunks;
    std::vector<Slot> m_slots;
    std::atomic<uint64_t> m_next{0};
    std::atomic<bool> m_abort{false};
    std::mutex m_mutex;
    std::condition_variable m_cv;
    // Guarded by m_mutex:
    uint64_t m_merged = 0;  // chunks merged so far
    uint64_t m_traced = 0;  // paths traced so far
    uint64_t m_reports = 0; // chunks reported by workers
    bool m_broken = false;  // a cut-short chunk was met in order
};

// Joins the workers however the calling thread leaves (a throwing progress callback too).
struct Joiner {
    ChunkRunner& runner;
    std::vector<std::thread>& threads;
    ~Joiner() {
        if (!threads.empty() && threads.front().joinable()) runner.abort();
        for (auto& th : threads)
            if (th.joinable()) th.join();
    }
};

} // namespace

SlabResult runSlab(const Medium& m, const SlabSettings& s,
                   const std::function<void(uint64_t done)>& progress,
                   const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    core::Stopwatch clock;
    const uint64_t chunks = (s.paths + kChunkPaths - 1) / kChunkPaths;
    const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const uint64_t want = static_cast<uint64_t>(s.threads > 0 ? s.threads : hw);
    const int workers = static_cast<int>(std::min(want, chunks));
    SlabTally t = makeTally(s);
    ChunkRunner runner(m, s, workers);
    std::vector<std::thread> threads;
    {
        Joiner joiner{runner, threads};
        threads.reserve(static_cast<size_t>(workers));
        for (int i = 0; i < workers; ++i)
            threads.emplace_back([&runner] { runner.work(); });
        using namespace std::chrono_literals;
        auto lastReport = std::chrono::steady_clock::now();
        uint64_t seen = 0;
        while (!runner.finished()) {
            if (cancel && cancel->load(std::memory_order_relaxed)) {
                runner.abort();
                break;
            }
            runner.mergeReady(t);
            const auto now = std::chrono::steady_clock::now();
            if (progress && now - lastReport >= 50ms) {
                progress(runner.traced());
                lastReport = now;
            }
            if (!runner.finished()) runner.waitForChunk(seen, 50ms);
        }
        for (auto& th : threads)
            th.join();
        runner.mergeReady(t); // after an abort: the chunks finished in order before the cut
    }
    if (progress) progress(t.paths);
    SlabResult r = finalize(t, s);
    r.seconds = clock.ms() / 1000.0;
    return r;
}

} // namespace pathtrace
