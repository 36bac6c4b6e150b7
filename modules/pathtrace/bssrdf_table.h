// pathtrace/bssrdf_table: the BSSRDF table file (`.bwtable`) — the raw sums of an estimate
// (bssrdf_estimate.h) for every incidence angle, with everything needed to finish, merge and
// check it. Format version 1 (documented in materials/README.md):
//   line 1   "bssrdf-workbench table"
//   line 2   one JSON object: {"version": 1, "medium": {...}, "settings": {...} (the
//            EstimateSettings description, threads omitted), "chunks": [[first, last), ...]
//            (chunk ranges of kChunkPaths paths traced, sorted and disjoint), "values": K
//            (exact sums per angle), "payload_bytes": N}
//   payload  per angle: paths (u64), truncated paths (u64), paths per batch (32 × u64, when
//            the header's "batches" (version 4 on) is 32), then K exact sums in the order
//            binSum, binSumSq, dirSum, dirSumSq, exit, exit², absorbed, absorbed², roulette,
//            roulette², truncated, truncated², energy, energy², events, and (with batches) the
//            batch sums batch-major; each exact sum is hi (i128) then lo (u128), 32 bytes,
//            little-endian.
// Shards of one run (`--shard K/N`) are tables over disjoint chunk ranges; mergeTables adds
// their exact sums, so the merge of all shards is bitwise the table of one run.
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pathtrace {

// Version 2 added settings.splitting; a version-1 table reads as a walk without splitting.
// Version 3 added settings.exits; an older table reads as a walk that tallied actual exits.
// Version 4 added the batch sums (BssrdfTally::batchSum, batchPaths); an older table has none.
constexpr int kTableVersion = 4;

struct BssrdfTable {
    Medium medium;
    EstimateSettings settings;
    std::vector<std::pair<uint64_t, uint64_t>> chunks; // chunk ranges traced
    std::vector<BssrdfTally> tallies;                  // one per settings.thetaIDeg entry

    // Whether the chunks cover every chunk of settings.paths.
    bool complete() const;
    // The finished slice of angle `i`.
    BssrdfSlice slice(size_t i) const;
};

// Runs the chunks [first, last) of every angle (progress: paths done over all angles). When
// `cancel` is set, the table covers the chunks completed so far (a valid table, mergeable like
// a shard); interrupted before every angle had the same chunks, it throws core::Error.
BssrdfTable estimateTable(const Medium& m, const EstimateSettings& s, uint64_t firstChunk,
                          uint64_t lastChunk, const std::function<void(uint64_t)>& progress = {},
                          const std::atomic<bool>* cancel = nullptr);

// Writes the file (core::Error naming the path when it cannot, or when a sum overflowed).
void writeTable(const std::filesystem::path& path, const BssrdfTable& t);
// Reads and checks a table; core::Error(path, 0, msg) when the first line is not a table's, the
// version is not kTableVersion, the header is malformed or its medium/settings are invalid, the
// payload is truncated or too long, a sum that cannot be negative is, or the path counts do not
// match the chunk ranges.
BssrdfTable readTable(const std::filesystem::path& path);
// Merges shards of one run: same medium and settings (core::Error naming the file and the
// field that differs), disjoint chunk ranges (core::Error naming both files).
BssrdfTable mergeTables(const std::vector<BssrdfTable>& tables,
                        const std::vector<std::string>& names);

// The table settings of a slab run (θi 0, one θs bin, one cell, the slab's bins): `slab --shard`
// writes such tables, and runSlab computes exactly their sums.
EstimateSettings slabTableSettings(const SlabSettings& s);
// A slab-shaped table as the slab reference's result, with `s` set to its settings (bins, rMax,
// paths, seed, estimator, termination). core::Error naming `what` when the table is not one.
SlabResult slabResultOf(const BssrdfTable& t, SlabSettings& s, const std::string& what);

// CSV of the directionally integrated R per spatial bin, one row per (θi, bin):
//   theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,R,stderr
std::string tableCsv(const BssrdfTable& t);
// CSV of S per directional cell:
//   theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,theta_o_deg,phi_o_deg,
//   solid_angle_sr,S,stderr   (θo = acos of the ring's middle cos, φo the sector's middle)
std::string tableDirCsv(const BssrdfTable& t);

} // namespace pathtrace
