// pathtrace/bssrdf_table: reading, writing, merging and CSV export of BSSRDF tables (format in
// bssrdf_table.h).
#include "pathtrace/bssrdf_table.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "pathtrace/detail/slab_connections.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>

namespace pathtrace {
namespace {

constexpr const char* kMagic = "bssrdf-workbench table";

// The exact sums of a tally in file order (the batch sums when `batches`).
template <class T, class F> void forEachSum(T& t, bool batches, F&& f) {
    for (auto* v : {&t.binSum, &t.binSumSq, &t.dirSum, &t.dirSumSq})
        for (auto& s : *v)
            f(s, v == &t.binSumSq || v == &t.dirSumSq);
    f(t.exitSum, false);
    f(t.exitSumSq, true);
    f(t.absSum, false);
    f(t.absSumSq, true);
    f(t.rouletteSum, false);
    f(t.rouletteSumSq, true);
    f(t.truncSum, false);
    f(t.truncSumSq, true);
    f(t.energySum, false);
    f(t.energySumSq, true);
    f(t.events, false);
    if (batches)
        for (auto& s : t.batchSum) // version 4 on: the batch sums, batch-major
            f(s, false);
}
// Exact sums per angle, with the batch sums when the table has them.
size_t sumsPerAngle(const BssrdfBins& b, bool batches) {
    const size_t nS = size_t(b.spatialBins()), nD = b.dirBins() > 1 ? nS * size_t(b.dirBins()) : 0;
    return 2 * nS + 2 * nD + 11 + (batches ? kBatches * nS : 0);
}
// Bytes per angle before the sums: paths, truncated paths and, with batches, paths per batch.
size_t countBytes(bool batches) {
    return 16 + (batches ? 8 * kBatches : 0);
}
// Sums that can never be negative: squares, bins, exits, absorbed, truncated, events.
bool nonNegative(const BssrdfTally& t, const detail::ExactSum& s, bool square) {
    return square || (&s != &t.rouletteSum && &s != &t.energySum);
}

nlohmann::json settingsJson(const EstimateSettings& s) {
    return core::toJson(s);
}

void put64(std::string& out, uint64_t v) {
    char b[8];
    std::memcpy(b, &v, 8);
    out.append(b, 8);
}
uint64_t get64(const char* p) {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}

} // namespace

bool BssrdfTable::complete() const {
    uint64_t next = 0;
    for (const auto& [a, b] : chunks) {
        if (a != next) return false;
        next = b;
    }
    return next == chunkCount(settings);
}

BssrdfSlice BssrdfTable::slice(size_t i) const {
    return finalize(tallies.at(i), settings.bins, settings.thetaIDeg.at(i), medium);
}

BssrdfTable estimateTable(const Medium& m, const EstimateSettings& s, uint64_t firstChunk,
                          uint64_t lastChunk, const std::function<void(uint64_t)>& progress,
                          const std::atomic<bool>* cancel) {
    BssrdfTable t;
    t.medium = m;
    t.settings = s;
    lastChunk = std::min(lastChunk, chunkCount(s));
    t.chunks = {{firstChunk, std::max(firstChunk, lastChunk)}};
    uint64_t before = 0;
    for (size_t a = 0; a < s.thetaIDeg.size(); ++a) {
        auto angleProgress = [&](uint64_t done) {
            if (progress) progress(before + done);
        };
        t.tallies.push_back(estimateChunks(m, s, a, firstChunk, lastChunk, angleProgress, cancel));
        before += t.tallies.back().paths;
        if (cancel && cancel->load()) break;
    }
    if (cancel && cancel->load()) {
        // Interrupted: the table covers the completed prefix of chunks, which must be the same
        // for every angle (angles are traced one after another).
        if (t.tallies.size() != s.thetaIDeg.size())
            throw core::Error("estimate", 0,
                              "interrupted while tracing theta_i " +
                                  core::formatNumber(s.thetaIDeg[t.tallies.size() - 1]) +
                                  " before the other angles were done: no consistent partial "
                                  "table (angles are traced one after another)");
        const uint64_t paths = t.tallies.front().paths;
        for (const BssrdfTally& tally : t.tallies)
            if (tally.paths != paths)
                throw core::Error("estimate", 0,
                                  "interrupted with unequal paths per angle: no consistent "
                                  "partial table");
        const uint64_t firstPath = firstChunk * kChunkPaths;
        const uint64_t end = std::min(lastChunk * kChunkPaths, s.paths);
        if (firstPath + paths < end) {
            if (paths % kChunkPaths != 0)
                throw core::Error("estimate", 0, "interrupted inside a chunk");
            t.chunks = {{firstChunk, firstChunk + paths / kChunkPaths}};
        }
    }
    return t;
}

void writeTable(const std::filesystem::path& path, const BssrdfTable& t) {
    std::string payload;
    // batches when every angle's tally kept them (the GL walk and older tables keep none)
    bool batches = !t.tallies.empty();
    for (const BssrdfTally& tally : t.tallies)
        batches = batches && !tally.batchSum.empty();
    for (const BssrdfTally& tally : t.tallies) {
        put64(payload, tally.paths);
        put64(payload, tally.truncatedPaths);
        if (batches)
            for (uint64_t n : tally.batchPaths)
                put64(payload, n);
        forEachSum(tally, batches, [&](const detail::ExactSum& s, bool) {
            if (s.overflow)
                throw core::Error(path.string(), 0, "a sum overflowed; the table cannot be stored");
            const auto hi = static_cast<unsigned __int128>(s.hi);
            put64(payload, uint64_t(hi));
            put64(payload, uint64_t(hi >> 64));
            put64(payload, uint64_t(s.lo));
            put64(payload, uint64_t(s.lo >> 64));
        });
    }
    nlohmann::json h;
    h["version"] = kTableVersion;
    h["medium"] = core::toJson(t.medium);
    h["settings"] = settingsJson(t.settings);
    h["chunks"] = nlohmann::json::array();
    for (const auto& [a, b] : t.chunks)
        h["chunks"].push_back({a, b});
    h["batches"] = batches ? kBatches : 0;
    h["values"] = sumsPerAngle(t.settings.bins, batches);
    h["payload_bytes"] = payload.size();
    core::writeFile(path, std::string(kMagic) + "\n" + h.dump() + "\n" + payload);
}

BssrdfTable readTable(const std::filesystem::path& path) {
    const std::string file = path.string();
    auto fail = [&](const std::string& msg) { throw core::Error(file, 0, msg); };
    const std::string bytes = core::readFile(path);
    const size_t l1 = bytes.find('\n');
    if (l1 == std::string::npos || bytes.compare(0, l1, kMagic) != 0)
        fail("not a BSSRDF table: the first line must be '" + std::string(kMagic) + "'");
    const size_t l2 = bytes.find('\n', l1 + 1);
    if (l2 == std::string::npos) fail("truncated: the header line has no end");
    nlohmann::json h;
    try {
        h = nlohmann::json::parse(bytes.substr(l1 + 1, l2 - l1 - 1));
    } catch (const nlohmann::json::exception& e) {
        throw core::Error(file, 2, std::string("header: ") + e.what());
    }
    if (!h.is_object() || !h.contains("version") || !h["version"].is_number_integer())
        throw core::Error(file, 2, "header: no integer 'version'");
    const long long version = h["version"].get<long long>();
    if (version < 1 || version > kTableVersion)
        throw core::Error(file, 2,
                          "table version " + h["version"].dump() +
                              "; this build reads versions 1 to " + std::to_string(kTableVersion));
    BssrdfTable t;
    if (version == 1) t.settings.splitting.levels = 0; // version 1 walks did not split
    if (version <= 2) t.settings.exits.samples = 0;    // before version 3: actual exits
    for (const char* key : {"medium", "settings", "chunks", "values", "payload_bytes"})
        if (!h.contains(key)) throw core::Error(file, 2, std::string("header: no '") + key + "'");
    core::fromJson(h["medium"], t.medium, file, "medium");
    core::fromJson(h["settings"], t.settings, file, "settings");
    try {
        validate(t.medium, file);
        validate(t.settings);
    } catch (const core::Error& e) {
        throw core::Error(file, 2, std::string("header: ") + e.what());
    }
    if (!h["chunks"].is_array()) throw core::Error(file, 2, "header: 'chunks' must be an array");
    uint64_t prev = 0, expectPaths = 0;
    for (const auto& c : h["chunks"]) {
        if (!c.is_array() || c.size() != 2 || !c[0].is_number_unsigned() ||
            !c[1].is_number_unsigned())
            throw core::Error(file, 2, "header: each chunk range must be [first, last]");
        const uint64_t a = c[0].get<uint64_t>(), b = c[1].get<uint64_t>();
        if (a < prev || b < a || b > chunkCount(t.settings))
            throw core::Error(file, 2,
                              "header: chunk ranges must be sorted, disjoint and within "
                              "the run's " +
                                  std::to_string(chunkCount(t.settings)) + " chunks");
        prev = b;
        t.chunks.emplace_back(a, b);
        expectPaths += std::min(b * kChunkPaths, t.settings.paths) - a * kChunkPaths;
    }
    bool batches = false; // version 4 on: "batches" is 32 (kept) or 0
    if (version >= 4) {
        if (!h.contains("batches") || !h["batches"].is_number_unsigned() ||
            (h["batches"].get<uint64_t>() != kBatches && h["batches"].get<uint64_t>() != 0))
            throw core::Error(file, 2,
                              "header: 'batches' must be " + std::to_string(kBatches) + " or 0");
        batches = h["batches"].get<uint64_t>() == kBatches;
        if (batches && t.settings.bins.spatialBins() > kMaxBatchedBins)
            throw core::Error(file, 2,
                              "header: batches are kept for at most " +
                                  std::to_string(kMaxBatchedBins) + " spatial bins");
    }
    const size_t k = sumsPerAngle(t.settings.bins, batches);
    if (!h["values"].is_number_unsigned() || h["values"].get<uint64_t>() != k)
        throw core::Error(file, 2,
                          "header: 'values' must be " + std::to_string(k) + " for these bins");
    const size_t angles = t.settings.thetaIDeg.size();
    const size_t expect = angles * (countBytes(batches) + 32 * k);
    const size_t have = bytes.size() - (l2 + 1);
    if (!h["payload_bytes"].is_number_unsigned() || h["payload_bytes"].get<uint64_t>() != expect)
        throw core::Error(file, 2, "header: 'payload_bytes' must be " + std::to_string(expect));
    if (have < expect)
        fail("truncated: " + std::to_string(have) + " bytes of payload, expected " +
             std::to_string(expect));
    if (have > expect) fail(std::to_string(have - expect) + " bytes after the payload's end");
    const char* p = bytes.data() + l2 + 1;
    for (size_t a = 0; a < angles; ++a) {
        BssrdfTally tally = makeTally(t.settings.bins);
        tally.paths = get64(p);
        tally.truncatedPaths = get64(p + 8);
        p += 16;
        if (tally.paths != expectPaths)
            fail("theta_i " + core::formatNumber(t.settings.thetaIDeg[a]) + ": " +
                 std::to_string(tally.paths) + " paths, but the chunk ranges hold " +
                 std::to_string(expectPaths));
        if (batches) {
            uint64_t inBatches = 0;
            for (uint64_t& n : tally.batchPaths) {
                n = get64(p);
                p += 8;
                inBatches += n;
            }
            if (inBatches != tally.paths)
                fail("theta_i " + core::formatNumber(t.settings.thetaIDeg[a]) + ": " +
                     std::to_string(inBatches) + " paths in the batches, but " +
                     std::to_string(tally.paths) + " in all");
        } else {
            tally.batchSum.clear(); // none kept (the GL walk, or a table before version 4)
        }
        size_t index = 0;
        forEachSum(tally, batches, [&](detail::ExactSum& s, bool square) {
            const unsigned __int128 hi =
                (static_cast<unsigned __int128>(get64(p + 8)) << 64) | get64(p);
            s.hi = static_cast<__int128>(hi);
            s.lo = (static_cast<unsigned __int128>(get64(p + 24)) << 64) | get64(p + 16);
            p += 32;
            if (s.hi < 0 && nonNegative(tally, s, square))
                fail("theta_i " + core::formatNumber(t.settings.thetaIDeg[a]) + ": value " +
                     std::to_string(index) + " is negative (" + core::formatNumber(s.value()) +
                     "), which no tally can be");
            ++index;
        });
        t.tallies.push_back(std::move(tally));
    }
    return t;
}

BssrdfTable mergeTables(const std::vector<BssrdfTable>& tables,
                        const std::vector<std::string>& names) {
    if (tables.empty()) throw core::Error("merge", 0, "no tables to merge");
    BssrdfTable out = tables[0];
    const std::string medium0 = core::toJson(out.medium).dump();
    std::vector<std::pair<std::pair<uint64_t, uint64_t>, size_t>> ranges;
    for (const auto& c : out.chunks)
        ranges.push_back({c, 0});
    for (size_t i = 1; i < tables.size(); ++i) {
        const BssrdfTable& t = tables[i];
        if (core::toJson(t.medium).dump() != medium0)
            throw core::Error(names[i], 0,
                              "medium " + core::toJson(t.medium).dump() + " differs from " +
                                  names[0] + "'s " + medium0);
        const auto a = settingsJson(out.settings), b = settingsJson(t.settings);
        for (auto it = a.begin(); it != a.end(); ++it)
            if (b[it.key()] != it.value())
                throw core::Error(names[i], 0,
                                  "settings." + it.key() + " " + b[it.key()].dump() +
                                      " differs from " + names[0] + "'s " + it.value().dump());
        for (const auto& c : t.chunks)
            ranges.push_back({c, i});
        for (size_t k = 0; k < out.tallies.size(); ++k)
            out.tallies[k].merge(t.tallies[k]);
    }
    std::sort(ranges.begin(), ranges.end());
    out.chunks.clear();
    for (size_t i = 0; i < ranges.size(); ++i) {
        const auto [range, who] = ranges[i];
        if (range.first == range.second) continue;
        if (i > 0 && range.first < ranges[i - 1].first.second)
            throw core::Error(names[who], 0,
                              "its chunks overlap those of " + names[ranges[i - 1].second] +
                                  ": they are the same shard, or shards of runs with other "
                                  "--shard counts");
        if (!out.chunks.empty() && out.chunks.back().second == range.first)
            out.chunks.back().second = range.second;
        else
            out.chunks.push_back(range);
    }
    return out;
}

EstimateSettings slabTableSettings(const SlabSettings& s) {
    return detail::estimateSettingsOf(s);
}

SlabResult slabResultOf(const BssrdfTable& t, SlabSettings& s, const std::string& what) {
    const EstimateSettings& e = t.settings;
    if (e.thetaIDeg != std::vector<double>{0.0} || e.bins.thetaSBins != 1 ||
        e.bins.dirBins() != 1 || e.bins.spacing != RadialSpacing::Uniform || e.bins.rStartMm != 0 ||
        e.orders != ScatterOrders::All)
        throw core::Error(what, 0,
                          "not a slab table (it needs theta_i 0, one theta_s bin, one direction "
                          "cell, uniform bins from 0, all orders): write it with `slab --shard`");
    s.bins = e.bins.rBins;
    s.rMaxMm = e.bins.rMaxMm;
    s.paths = e.paths;
    s.seed = e.seed;
    s.termination = e.termination;
    s.splitting = e.splitting;
    s.exits = e.exits;
    s.estimator = e.estimator == BssrdfEstimator::Analog     ? Estimator::Analog
                  : e.estimator == BssrdfEstimator::Implicit ? Estimator::Implicit
                                                             : Estimator::Connections;
    return finalize(detail::slabTallyOf(t.tallies.at(0), t.medium), s);
}

namespace {
double deg(double rad) {
    return rad * 180.0 / std::numbers::pi;
}
} // namespace

std::string tableCsv(const BssrdfTable& t) {
    const BssrdfBins& b = t.settings.bins;
    const auto e = b.rEdges();
    std::ostringstream out;
    out << "theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,R,stderr\n";
    for (size_t a = 0; a < t.tallies.size(); ++a) {
        const BssrdfSlice s = t.slice(a);
        for (int ir = 0; ir < b.rBins; ++ir)
            for (int it = 0; it < b.thetaSBins; ++it) {
                const size_t i = size_t(ir * b.thetaSBins + it);
                out << core::formatNumber(s.thetaIDeg) << ',' << core::formatNumber(e[size_t(ir)])
                    << ',' << core::formatNumber(e[size_t(ir) + 1]) << ','
                    << core::formatNumber(180.0 * it / b.thetaSBins) << ','
                    << core::formatNumber(180.0 * (it + 1) / b.thetaSBins) << ','
                    << core::formatNumber(s.R[i]) << ',' << core::formatNumber(s.RStderr[i])
                    << '\n';
            }
    }
    return out.str();
}

std::string tableDirCsv(const BssrdfTable& t) {
    const BssrdfBins& b = t.settings.bins;
    const auto e = b.rEdges();
    const int nD = b.dirBins();
    std::ostringstream out;
    out << "theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,theta_o_deg,phi_o_deg,"
           "solid_angle_sr,S,stderr\n";
    for (size_t a = 0; a < t.tallies.size(); ++a) {
        const BssrdfSlice s = t.slice(a);
        for (int ir = 0; ir < b.rBins; ++ir)
            for (int it = 0; it < b.thetaSBins; ++it)
                for (int c = 0; c < nD; ++c) {
                    const size_t bin = size_t(ir * b.thetaSBins + it);
                    const int ring = c / b.dirPhiBins, sector = c % b.dirPhiBins;
                    const double mu = (ring + 0.5) / b.dirCosBins;
                    // With one cell, S is R over the hemisphere's projected solid angle π.
                    const double v =
                        nD > 1 ? s.S[bin * size_t(nD) + size_t(c)] : s.R[bin] / std::numbers::pi;
                    const double ev = nD > 1 ? s.SStderr[bin * size_t(nD) + size_t(c)]
                                             : s.RStderr[bin] / std::numbers::pi;
                    out << core::formatNumber(s.thetaIDeg) << ','
                        << core::formatNumber(e[size_t(ir)]) << ','
                        << core::formatNumber(e[size_t(ir) + 1]) << ','
                        << core::formatNumber(180.0 * it / b.thetaSBins) << ','
                        << core::formatNumber(180.0 * (it + 1) / b.thetaSBins) << ','
                        << core::formatNumber(deg(std::acos(mu))) << ','
                        << core::formatNumber(360.0 * (sector + 0.5) / b.dirPhiBins) << ','
                        << core::formatNumber(2 * std::numbers::pi / nD) << ','
                        << core::formatNumber(v) << ',' << core::formatNumber(ev) << '\n';
                }
    }
    return out.str();
}

} // namespace pathtrace
