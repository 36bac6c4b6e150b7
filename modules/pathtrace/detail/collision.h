// pathtrace: the per-collision weight bookkeeping shared by every CPU walk (slab, sphere,
// mesh): absorption by weight w ← ϖw with w(1 − ϖ) deposited, Russian roulette below a
// weight threshold (survivors divided by the survival probability, so a survivor's weight
// stays below rouletteWeight/p: bounded), and truncation after maxEvents interactions.
// `loss` accumulates what roulette removes minus what it adds, so per path
// reflected + absorbed + truncated + loss (+ specular) = 1 exactly; E[loss] = 0.
#pragma once

#include <cstdint>

namespace pathtrace::detail {

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

// Truncation after `events` interactions: the path ends and its weight is the truncated
// weight (a bound on the bias: that weight would have left or been absorbed later). Returns
// false when the path ends.
template <class Consts>
inline bool belowEventLimit(double w, double& truncated, uint32_t events, const Consts& c) {
    if (events < c.maxEvents) return true;
    truncated += w; // a path's copies (radial splitting) add up
    return false;
}

} // namespace pathtrace::detail
