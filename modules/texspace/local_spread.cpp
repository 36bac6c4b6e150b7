// How far another driver may move the hybrid's local term (texspace/pipeline.h,
// Pipeline::localSpread). Two of the local term's inputs are a driver's choice within the GL
// specification, and each moves B_l where a tap's place meets an edge:
//   - the light-view map is a rasterisation: GL_SUBPIXEL_BITS >= 4 lets two drivers' images lie
//     irradiance::kRasterShiftTexels (1/16 texel) apart, so a silhouette texel seen by one is
//     empty for the other, and every texel holds the surface at a slightly other point;
//   - each tap's texel is floor(uv · M) of a uv that hybrid_local.comp forms from dot products a
//     driver may fuse and a division GLSL allows 2.5 ulp: uv · M lies a few ulp of uv · M (M ≤
//     4096: 2^-12 texel each) apart, so a tap that close to a texel's edge reads the neighbour.
// Measured here per tap, as irradiance::Stage::visibilitySpread measures V's per point, and
// summed over the taps, per pixel and channel: Σ_taps (the largest |term(map drawn to one of
// irradiance::rasterShifts()) − term| + the largest |term(read 2^-10 texel aside, the same eight
// ways) − term|). Per tap, not per pixel: a driver snaps each vertex on its own, so each tap
// reads the surface moved its own way, while a whole-map move shifts every tap of a ring alike
// and their changes cancel (a pixel's L moved 3.7x past the whole-map measure with the vertices
// snapped 1/16 texel apart, and past it even at 1/256:
// CaptureReplay.TheLocalSpreadBoundsALightMapWhoseVerticesSnapApart). A tap's term is close
// to linear in its move, whose largest change over the square is at a corner; where a tap's
// texel changes surface the midpoints count too (irradiance::rasterShifts).
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

void Pipeline::setLocalVertexSnap(const gl::VertexSnap& snap) {
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
    const int size = m_run.local.lightMapSize;
    const float lookupScale = (1.0f / 1024.0f) / irradiance::kRasterShiftTexels;
    std::vector<glm::vec3> spread;
    spread.reserve(pixels.size());
    beginLocal(); // the run's map, lookups and inputs
    const size_t pass = m_local->tapsPerPass();
    for (size_t first = 0; first < pixels.size(); first += pass) {
        const size_t n = std::min(pass, pixels.size() - first);
        m_local->beginTaps(std::vector<uint32_t>(pixels.begin() + std::ptrdiff_t(first),
                                                 pixels.begin() + std::ptrdiff_t(first + n)));
        for (const glm::vec2 shift : irradiance::rasterShifts()) { // group 0: the map
            m_local->renderLightMap(m_light.direction, size, m_mapShift + shift);
            m_local->raiseTaps(0);
        }
        m_local->renderLightMap(m_light.direction, size, m_mapShift);
        for (const glm::vec2 shift : irradiance::rasterShifts()) { // group 1: the lookups
            m_local->setLookupShift(m_lookupShift + lookupScale * shift);
            m_local->raiseTaps(1);
        }
        m_local->setLookupShift(m_lookupShift);
        const std::vector<glm::vec3> part = m_local->tapSpreads();
        spread.insert(spread.end(), part.begin(), part.end());
    }
    return spread;
}

} // namespace texspace
