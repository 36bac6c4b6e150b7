// pathtrace/detail/exact_sum: an exact, order-independent sum of doubles in 256-bit fixed point
//   (a long accumulator in the sense of Kulisch & Miranker 1986, cut to the range a tally needs;
//   written here because no packaged library offers a small fixed-width one).
//   The value is hi + lo·2^-128 with hi a signed 128-bit integer and lo an unsigned 128-bit
//   fraction, so it holds any |x| < 2^126 to a resolution of 2^-128 (3e-39). Adding a double
//   first truncates it toward zero at 2^-128 (a deterministic function of that double alone);
//   every later addition is integer arithmetic, exact, associative and commutative. So chunk
//   sums added in any order, on any number of threads or machines (shards), give the same bits.
//   Doubles with |x| ≥ 2^120 (or non-finite) set `overflow`, which the readers report.
#pragma once

#include <cmath>
#include <cstdint>

namespace pathtrace::detail {

struct ExactSum {
    __int128 hi = 0;          // integer part (two's complement)
    unsigned __int128 lo = 0; // fraction, units of 2^-128
    bool overflow = false;

    void add(const ExactSum& o) {
        const unsigned __int128 l = lo + o.lo;
        hi += o.hi + (l < lo ? 1 : 0);
        lo = l;
        overflow = overflow || o.overflow;
    }
    void add(double x) {
        if (x == 0) return;
        if (!std::isfinite(x) || std::fabs(x) >= 0x1p120) {
            overflow = true;
            return;
        }
        ExactSum m = fromMagnitude(std::fabs(x));
        if (x < 0) m.negate();
        add(m);
    }
    // The value rounded to a double (a function of the exact state only).
    double value() const {
        // hi + lo·2^-128 with both parts converted separately: the error is within a few ulps
        // of the result and, like everything here, deterministic.
        return static_cast<double>(hi) + std::ldexp(static_cast<double>(lo), -128);
    }
    bool operator==(const ExactSum& o) const {
        return hi == o.hi && lo == o.lo && overflow == o.overflow;
    }

  private:
    void negate() {
        // Two's complement of the 256-bit number (hi, lo).
        lo = ~lo + 1;
        hi = ~hi + (lo == 0 ? 1 : 0);
    }
    // |x| in (0, 2^120): split the 53-bit significand at the binary point.
    static ExactSum fromMagnitude(double a) {
        int e = 0;
        const double f = std::frexp(a, &e);                      // a = f·2^e, f in [0.5, 1)
        const auto m = static_cast<uint64_t>(std::ldexp(f, 53)); // a = m·2^(e − 53), exact
        const int shift = e - 53;                                // a = m · 2^shift
        ExactSum s;
        if (shift >= 0) {
            s.hi = static_cast<__int128>(m) << shift;
            return s;
        }
        const int down = -shift; // bits of m below the binary point
        if (down < 64) s.hi = static_cast<__int128>(m >> down);
        // The fraction bits: m · 2^(128 − down) mod 2^128, truncated below 2^-128.
        const int up = 128 - down;
        if (up >= 0) {
            s.lo = up >= 128 ? 0 : static_cast<unsigned __int128>(m) << up;
        } else if (-up < 64) {
            s.lo = static_cast<unsigned __int128>(m >> -up);
        }
        return s;
    }
};

} // namespace pathtrace::detail
