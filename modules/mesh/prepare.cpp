// mesh preparation for the point-cloud pipeline (mesh.h prepareRenderable): finite vertices,
// no zero-area triangles, some area, normalised to one unit on the longest axis.
#include "core/core.h"
#include "mesh/mesh.h"

#include <cmath>

namespace mesh {

RenderablePrep prepareRenderable(Mesh& m, const std::string& name) {
    RenderablePrep r;
    for (size_t i = 0; i < m.vertices.size(); ++i)
        for (float c : m.vertices[i])
            if (!std::isfinite(c))
                throw core::Error(name, 0,
                                  "vertex " + std::to_string(i + 1) +
                                      " has a non-finite coordinate (NaN or Inf)");
    std::vector<std::array<uint32_t, 3>> kept;
    kept.reserve(m.triangles.size());
    double area = 0;
    for (const auto& t : m.triangles) {
        const auto& a = m.vertices[t[0]];
        const auto& b = m.vertices[t[1]];
        const auto& c = m.vertices[t[2]];
        const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double x = e1[1] * e2[2] - e1[2] * e2[1];
        const double y = e1[2] * e2[0] - e1[0] * e2[2];
        const double z = e1[0] * e2[1] - e1[1] * e2[0];
        const double twice = std::sqrt(x * x + y * y + z * z);
        if (!(twice > 0)) {
            ++r.droppedDegenerate;
            continue;
        }
        area += 0.5 * twice;
        kept.push_back(t);
    }
    if (kept.empty() || !(area > 0))
        throw core::Error(name, 0,
                          "the mesh has no surface area (all " +
                              std::to_string(m.triangles.size()) + " triangles are degenerate)");
    m.triangles = std::move(kept);
    r.originalLongestAxis = normalizeMesh(m, name);
    return r;
}

} // namespace mesh
