// How far another driver may move the hybrid's local term (texspace/pipeline.h,
// Pipeline::localSpread). Two of the local term's inputs are a driver's choice within the GL
// specification, and each moves B_l where a tap's place meets an edge:
//   - the light-view map is a rasterisation: GL_SUBPIXEL_BITS >= 4 lets two drivers' images lie
//     irradiance::kRasterShiftTexels (1/16 texel) apart, so a silhouette texel seen by one is
//     empty for the other, and every texel holds the surface at a slightly other point;
//   - each tap's texel is floor(uv · M) of a uv that hybrid_local.comp forms from dot products a
//     driver may fuse and a division GLSL allows 2.5 ulp: uv · M lies a few ulp of uv · M (M ≤
//     4096: 2^-12 texel each) apart, so a tap that close to a texel's edge reads the neighbour.
// Measured here, as irradiance::Stage::visibilitySpread measures V's, per pixel and channel: the
// largest |L(map drawn to one of irradiance::rasterShifts()) − L| (the map moves one way), plus
// Σ over ±x, ±y of |L(taps read 2^-10 texel that way) − L| (every tap within 4x that rounding of
// a texel's edge moved across it: different taps each way, so they add).
#include "texspace/pipeline.h"

#include "core/core.h"
#include "irradiance/irradiance.h"

#include <glm/common.hpp>

#include <algorithm>

namespace texspace {

void Pipeline::setLocalShift(glm::vec2 map, glm::vec2 lookup) {
    m_mapShift = map;
    m_lookupShift = lookup;
}

void Pipeline::setLocalVertexSnap(const irradiance::VertexSnap& snap) {
    m_localSnap = snap;
    m_lightMapSize = 0; // drawn again at the next begin()
}

std::vector<glm::vec3> Pipeline::localSpread(const std::vector<size_t>& pixels) {
    if (!m_run.hybrid || !m_local || m_ownLocalL.empty())
        throw core::Error("hybrid", 0, "the local term is not computed yet");
    for (size_t p : pixels)
        if (p >= m_ownLocalL.size())
            throw core::Error("hybrid", 0,
                              "pixel " + std::to_string(p) + " lies outside the frame of " +
                                  std::to_string(m_ownLocalL.size()));
    const float e = 1.0f / 1024.0f;
    const int size = m_run.local.lightMapSize;
    auto evaluate = [&](glm::vec2 map, glm::vec2 lookup) {
        m_local->renderLightMap(m_light.direction, size, m_mapShift + map);
        m_local->setLookupShift(m_lookupShift + lookup);
        beginLocal();
        while (!m_local->step(64)) {
        }
        return m_local->result().radiance;
    };
    std::vector<glm::vec3> spread(pixels.size(), glm::vec3(0.0f));
    auto difference = [&](const std::vector<glm::vec4>& moved, size_t i) {
        return glm::abs(glm::vec3(moved[pixels[i]]) - glm::vec3(m_ownLocalL[pixels[i]]));
    };
    for (const glm::vec2 shift : irradiance::rasterShifts()) { // the map: the worst move
        const std::vector<glm::vec4> moved = evaluate(shift, {});
        for (size_t i = 0; i < pixels.size(); ++i)
            spread[i] = glm::max(spread[i], difference(moved, i));
    }
    for (const glm::vec2 lookup : {glm::vec2(e, 0.0f), glm::vec2(-e, 0.0f), glm::vec2(0.0f, e),
                                   glm::vec2(0.0f, -e)}) { // the taps: every side adds
        const std::vector<glm::vec4> moved = evaluate({}, lookup);
        for (size_t i = 0; i < pixels.size(); ++i)
            spread[i] += difference(moved, i);
    }
    // the run's map and lookups again
    m_local->renderLightMap(m_light.direction, size, m_mapShift);
    m_local->setLookupShift(m_lookupShift);
    return spread;
}

} // namespace texspace
