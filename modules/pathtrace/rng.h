// pathtrace/rng: the random numbers of the tracers.
//   PCG32 (O'Neill 2014, "PCG: a family of simple fast space-efficient statistically good
//   algorithms for random number generation", generator PCG-XSH-RR 64/32) with one stream per
//   path: state and stream selector are derived from (seed, path index) through SplitMix64
//   (Steele, Lea & Flood 2014), so a path's numbers do not depend on which thread traced it or
//   on what was traced before (the thesis's Appendix A.1 asks the same of a PRNG: long period,
//   uniform, uncorrelated; its ANSI-C LCG is replaced by this better generator).
//   Uniform floats in [0, 1) are built from the top bits as exact multiples of 2^-k
//   (k = 24, 32 or 53), never 1.
#pragma once

#include <cstdint>

namespace pathtrace {

// SplitMix64 finaliser: a bijective 64-bit mixer (every output bit depends on every input bit).
constexpr uint64_t splitmix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

class Pcg32 {
  public:
    // pcg32_srandom_r(initstate, initseq).
    constexpr Pcg32(uint64_t initState, uint64_t initSeq) : m_state(0), m_inc((initSeq << 1) | 1) {
        nextU32();
        m_state += initState;
        nextU32();
    }
    // The stream of path `path` under `seed`: distinct paths get distinct (state, stream) pairs
    // (splitmix64 is a bijection, so key differs for every path of one seed).
    static constexpr Pcg32 forPath(uint64_t seed, uint64_t path) {
        const uint64_t key = splitmix64(splitmix64(seed) ^ path);
        return Pcg32(splitmix64(key), splitmix64(key ^ 0x5851f42d4c957f2dull));
    }

    constexpr uint32_t nextU32() {
        const uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    // Uniform in [0, 1), 53 random bits (two draws).
    constexpr double uniform() {
        const uint64_t hi = nextU32();
        const uint64_t lo = nextU32();
        return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1p-53;
    }
    // Uniform in [0, 1), 32 random bits (one draw): for decisions and angles.
    constexpr double uniform32() { return static_cast<double>(nextU32()) * 0x1p-32; }
    // Uniform in [0, 1) as a float, 24 random bits.
    constexpr float uniformFloat() { return static_cast<float>(nextU32() >> 8) * 0x1p-24f; }

  private:
    uint64_t m_state;
    uint64_t m_inc;
};

} // namespace pathtrace
