// pathtrace/detail/chunk_runner (see chunk_runner.h): worker pool, ring of chunk slots and
// in-order merging shared by the multi-threaded slab and image runners.
#include "pathtrace/detail/chunk_runner.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace pathtrace::detail {
namespace {

struct Slot {
    uint64_t chunk = 0;
    uint64_t count = 0;
    bool ready = false;    // traced and waiting to be merged
    bool complete = false; // all `count` paths traced (not cut short by cancel)
};

class ChunkRunner {
  public:
    ChunkRunner(uint64_t paths, uint64_t chunkPaths, const ChunkCallbacks& callbacks, int workers)
        : m_paths(paths), m_chunkPaths(chunkPaths), m_callbacks(callbacks),
          m_chunks((paths + chunkPaths - 1) / chunkPaths),
          m_slots(static_cast<size_t>(2 * workers)) {
        m_callbacks.allocate(m_slots.size());
    }

    // Worker loop: trace chunks in increasing order until none are left or the run is aborted.
    void work() {
        for (;;) {
            const uint64_t c = m_next.fetch_add(1);
            if (c >= m_chunks || aborted()) return;
            const size_t index = static_cast<size_t>(c % m_slots.size());
            Slot& slot = m_slots[index];
            {
                std::unique_lock lock(m_mutex);
                m_cv.wait(lock, [&] { return c < m_merged + m_slots.size() || aborted(); });
                if (aborted()) return;
            }
            const uint64_t first = c * m_chunkPaths;
            const uint64_t count = std::min(m_chunkPaths, m_paths - first);
            uint64_t got = 0;
            try {
                got = m_callbacks.trace(index, first, count, &m_abort);
            } catch (...) { // tracers do not throw; keep the run consistent if one does
                got = 0;
            }
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

    // Merges the chunks that are ready, in chunk order.
    void mergeReady() {
        for (;;) {
            Slot* slot = nullptr;
            size_t index = 0;
            {
                std::lock_guard lock(m_mutex);
                if (m_merged >= m_chunks || m_broken) return;
                index = static_cast<size_t>(m_merged % m_slots.size());
                Slot& s = m_slots[index];
                if (!s.ready || s.chunk != m_merged) return;
                if (!s.complete) {
                    m_broken = true; // a cut-short chunk ends the prefix
                    return;
                }
                slot = &s;
            }
            m_callbacks.merge(index, slot->count); // the slot is ours until marked free
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
    const uint64_t m_paths;
    const uint64_t m_chunkPaths;
    const ChunkCallbacks& m_callbacks;
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

void runChunks(uint64_t paths, uint64_t chunkPaths, int threads, const ChunkCallbacks& callbacks,
               const std::function<void(uint64_t done)>& progress,
               const std::atomic<bool>* cancel) {
    // Cancelled before the start: trace nothing (otherwise a worker could finish a chunk
    // before the loop below first looks at the flag, making the result depend on timing).
    if (cancel && cancel->load(std::memory_order_relaxed)) return;
    const uint64_t chunks = (paths + chunkPaths - 1) / chunkPaths;
    const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const uint64_t want = static_cast<uint64_t>(threads > 0 ? threads : hw);
    const int workers = static_cast<int>(std::min(want, chunks));
    ChunkRunner runner(paths, chunkPaths, callbacks, workers);
    std::vector<std::thread> pool;
    Joiner joiner{runner, pool};
    pool.reserve(static_cast<size_t>(workers));
    for (int i = 0; i < workers; ++i)
        pool.emplace_back([&runner] { runner.work(); });
    using namespace std::chrono_literals;
    auto lastReport = std::chrono::steady_clock::now();
    uint64_t seen = 0;
    while (!runner.finished()) {
        if (cancel && cancel->load(std::memory_order_relaxed)) {
            runner.abort();
            break;
        }
        runner.mergeReady();
        const auto now = std::chrono::steady_clock::now();
        if (progress && now - lastReport >= 50ms) {
            progress(runner.traced());
            lastReport = now;
        }
        if (!runner.finished()) runner.waitForChunk(seen, 50ms);
    }
    for (auto& th : pool)
        th.join();
    runner.mergeReady(); // after an abort: the chunks finished in order before the cut
}

} // namespace pathtrace::detail
