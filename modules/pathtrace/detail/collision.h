// pathtrace: the per-collision weight bookkeeping shared by every CPU walk (slab, sphere,
// mesh): absorption by weight w ← ϖw with w(1 − ϖ) deposited, Russian roulette below a
// weight threshold (survivors divided by the survival probability), and the thesis's
// long-path roulette (3.2): past `rouletteAfter` events terminate with 90 %, survive ×10.
// `loss` accumulates what roulette removes minus what it adds, so per path
// reflected + absorbed + loss (+ specular) = 1 exactly; E[loss] = 0 (both roulettes unbiased).
#pragma once

#include <cstdint>

namespace pathtrace::detail {

constexpr uint32_t kTenth = 429496730u; // 1/10 of 2^32: long-path roulette survival

// Implicit absorption and weight roulette at a collision. Returns false when the path ends.
template <class Consts, class Rng>
inline bool absorbAndRoulette(double& w, double& absorbed, double& loss, const Consts& c,
                              Rng& rng) {
    const double wn = w * c.albedo;
    absorbed += w - wn;
    w = wn;
    if (w >= c.rouletteWeight) return true;
    if (rng.uniform32() < c.rouletteSurvival) {
        const double ws = w / c.rouletteSurvival;
        loss -= ws - w;
        w = ws;
        return true;
    }
    loss += w;
    return false;
}

// Long-path roulette after `events` collisions. Returns false when the path ends.
template <class Consts, class Rng>
inline bool longPathRoulette(double& w, double& loss, uint32_t events, const Consts& c, Rng& rng) {
    if (events <= c.rouletteAfter) return true;
    if (rng.nextU32() < kTenth) {
        const double ws = w * 10.0;
        loss -= ws - w;
        w = ws;
        return true;
    }
    loss += w;
    return false;
}

} // namespace pathtrace::detail
