// pathtrace/camera_runner: multi-threaded image runs independent of the thread count (the
// scheme of run_slab.cpp). Paths are cut into chunks of kImageChunkPaths; worker threads take
// chunks in increasing order from an atomic counter and trace each into a ring slot of
// per-path records (2 slots per worker bound the memory; a worker waits for its slot to be
// merged); the calling thread adds the records into the tally path by path in chunk order,
// so every sum is formed in the same order for any thread count. The calling thread polls
// every 50 ms: it merges, reports progress and watches `cancel`; on cancel the workers stop and
// the tally keeps the completed prefix of chunks.
#include "pathtrace/camera.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace pathtrace {
namespace {

struct Slot {
    std::vector<ExitRecord> records; // channel-major: records[c·count + i]
    uint64_t chunk = 0;
    uint64_t count = 0;
    bool ready = false;
    bool complete = false;
};

class ChunkRunner {
  public:
    ChunkRunner(uint64_t paths, const ChunkTracer& trace, int workers)
        : m_paths(paths), m_trace(trace),
          m_chunks((paths + kImageChunkPaths - 1) / kImageChunkPaths),
          m_slots(static_cast<size_t>(2 * workers)) {
        for (auto& slot : m_slots)
            slot.records.resize(
                static_cast<size_t>(kChannels * std::min<uint64_t>(kImageChunkPaths, paths)));
    }

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
            const uint64_t first = c * kImageChunkPaths;
            const uint64_t count = std::min(kImageChunkPaths, m_paths - first);
            uint64_t got = 0;
            try {
                got = m_trace(first, count, slot.records.data(), &m_abort);
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
            if (got < count) return;
        }
    }

    void mergeReady(ImageTally& t) {
        for (;;) {
            Slot* slot = nullptr;
            {
                std::lock_guard lock(m_mutex);
                if (m_merged >= m_chunks || m_broken) return;
                Slot& s = m_slots[m_merged % m_slots.size()];
                if (!s.ready || s.chunk != m_merged) return;
                if (!s.complete) {
                    m_broken = true;
                    return;
                }
                slot = &s;
            }
            for (uint64_t i = 0; i < slot->count; ++i)
                t.add(slot->records.data(), slot->count, i);
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
    void waitForChunk(uint64_t& seen, std::chrono::milliseconds timeout) {
        std::unique_lock lock(m_mutex);
        m_cv.wait_for(lock, timeout, [&] { return m_reports != seen; });
        seen = m_reports;
    }

  private:
    const uint64_t m_paths;
    const ChunkTracer& m_trace;
    const uint64_t m_chunks;
    std::vector<Slot> m_slots;
    std::atomic<uint64_t> m_next{0};
    std::atomic<bool> m_abort{false};
    std::mutex m_mutex;
    std::condition_variable m_cv;
    uint64_t m_merged = 0;
    uint64_t m_traced = 0;
    uint64_t m_reports = 0;
    bool m_broken = false;
};

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

ImageTally runImageChunks(uint64_t paths, int threads, size_t pixels, const ChunkTracer& trace,
                          const std::function<void(uint64_t done)>& progress,
                          const std::atomic<bool>* cancel) {
    ImageTally t(pixels);
    if (paths == 0) return t;
    const uint64_t chunks = (paths + kImageChunkPaths - 1) / kImageChunkPaths;
    const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const uint64_t want = static_cast<uint64_t>(threads > 0 ? threads : hw);
    const int workers = static_cast<int>(std::min(want, chunks));
    ChunkRunner runner(paths, trace, workers);
    std::vector<std::thread> pool;
    {
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
            runner.mergeReady(t);
            const auto now = std::chrono::steady_clock::now();
            if (progress && now - lastReport >= 50ms) {
                progress(runner.traced());
                lastReport = now;
            }
            if (!runner.finished()) runner.waitForChunk(seen, 50ms);
        }
        for (auto& th : pool)
            th.join();
        runner.mergeReady(t);
    }
    if (progress) progress(t.paths);
    return t;
}

} // namespace pathtrace
