// mesh/topology: welding, vertex normals, the topology checks and normalisation (see mesh.h).
#include "mesh/mesh.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace mesh {
namespace {

// Up to 8 floats compared bitwise (−0 and +0 equal).
struct Key {
    std::array<uint32_t, 8> b{};
    bool operator==(const Key& o) const { return b == o.b; }
};
struct KeyHash {
    size_t operator()(const Key& k) const {
        uint64_t h = 1469598103934665603ull;
        for (uint32_t v : k.b)
            h = (h ^ v) * 1099511628211ull;
        return static_cast<size_t>(h);
    }
};
void putKey(Key& k, size_t at, float f) {
    if (f == 0.0f) f = 0.0f; // −0 and +0 weld
    std::memcpy(&k.b[at], &f, sizeof f);
}

struct EdgeUse {
    uint32_t forward = 0, backward = 0; // uses min→max, max→min
};

} // namespace

void weldVertices(Mesh& m) {
    const bool hasN = m.normals.size() == m.vertices.size() && !m.normals.empty();
    const bool hasUv = m.uvs.size() == m.vertices.size() && !m.uvs.empty();
    std::unordered_map<Key, uint32_t, KeyHash> index;
    std::vector<uint32_t> remap(m.vertices.size());
    std::vector<std::array<float, 3>> out, outN;
    std::vector<std::array<float, 2>> outUv;
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        Key k;
        for (size_t a = 0; a < 3; ++a)
            putKey(k, a, m.vertices[i][a]);
        if (hasN)
            for (size_t a = 0; a < 3; ++a)
                putKey(k, 3 + a, m.normals[i][a]);
        if (hasUv)
            for (size_t a = 0; a < 2; ++a)
                putKey(k, 6 + a, m.uvs[i][a]);
        auto [it, inserted] = index.emplace(k, static_cast<uint32_t>(out.size()));
        if (inserted) {
            out.push_back(m.vertices[i]);
            if (hasN) outN.push_back(m.normals[i]);
            if (hasUv) outUv.push_back(m.uvs[i]);
        }
        remap[i] = it->second;
    }
    std::vector<std::array<uint32_t, 3>> tris;
    tris.reserve(m.triangles.size());
    for (const auto& t : m.triangles) {
        const std::array<uint32_t, 3> r{remap[t[0]], remap[t[1]], remap[t[2]]};
        if (r[0] != r[1] && r[1] != r[2] && r[0] != r[2]) tris.push_back(r);
    }
    m.vertices = std::move(out);
    m.triangles = std::move(tris);
    if (hasN) m.normals = std::move(outN);
    if (hasUv) m.uvs = std::move(outUv);
}

void computeVertexNormals(Mesh& m) {
    std::vector<std::array<double, 3>> sum(m.vertices.size(), {0.0, 0.0, 0.0});
    for (const auto& t : m.triangles) {
        const auto& p = m.vertices[t[0]];
        const auto& q = m.vertices[t[1]];
        const auto& r = m.vertices[t[2]];
        const double e1[3] = {double(q[0]) - p[0], double(q[1]) - p[1], double(q[2]) - p[2]};
        const double e2[3] = {double(r[0]) - p[0], double(r[1]) - p[1], double(r[2]) - p[2]};
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]}; // |n| = 2 × area
        for (uint32_t v : t)
            for (size_t a = 0; a < 3; ++a)
                sum[v][a] += n[a];
    }
    m.normals.resize(m.vertices.size());
    for (size_t i = 0; i < sum.size(); ++i) {
        const double len =
            std::sqrt(sum[i][0] * sum[i][0] + sum[i][1] * sum[i][1] + sum[i][2] * sum[i][2]);
        if (len > 0 && std::isfinite(len))
            m.normals[i] = {static_cast<float>(sum[i][0] / len),
                            static_cast<float>(sum[i][1] / len),
                            static_cast<float>(sum[i][2] / len)};
        else
            m.normals[i] = {0.0f, 0.0f, 1.0f};
    }
}

MeshTopology analyseTopology(const Mesh& m) {
    // Vertices split by normals or UVs (sharp edges, seams) share their position: weld.
    std::unordered_map<Key, uint32_t, KeyHash> index;
    std::vector<uint32_t> pos(m.vertices.size());
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        Key k;
        for (size_t a = 0; a < 3; ++a)
            putKey(k, a, m.vertices[i][a]);
        pos[i] = index.emplace(k, static_cast<uint32_t>(i)).first->second;
    }
    MeshTopology t;
    std::unordered_map<uint64_t, EdgeUse> edges;
    edges.reserve(m.triangles.size() * 2);
    double vol = 0.0;
    for (const auto& tri : m.triangles) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = pos[tri[static_cast<size_t>(k)]],
                           b = pos[tri[static_cast<size_t>((k + 1) % 3)]];
            const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
            EdgeUse& e = edges[key];
            if (a < b)
                ++e.forward;
            else
                ++e.backward;
        }
        const auto& p = m.vertices[tri[0]];
        const auto& q = m.vertices[tri[1]];
        const auto& r = m.vertices[tri[2]];
        const double cx = double(q[1]) * r[2] - double(q[2]) * r[1];
        const double cy = double(q[2]) * r[0] - double(q[0]) * r[2];
        const double cz = double(q[0]) * r[1] - double(q[1]) * r[0];
        vol += p[0] * cx + p[1] * cy + p[2] * cz;
    }
    t.signedVolume = vol / 6.0;
    t.edges = edges.size();
    for (const auto& [key, e] : edges) {
        const uint32_t uses = e.forward + e.backward;
        if (uses == 1)
            ++t.boundaryEdges;
        else if (uses > 2)
            ++t.nonManifoldEdges;
        else if (e.forward != 1)
            ++t.inconsistentEdges;
    }
    return t;
}

void checkClosedOutward(const Mesh& m, const std::string& name) {
    if (m.triangles.empty()) throw core::Error(name, 0, "empty mesh: no triangles");
    for (const auto& v : m.vertices)
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw core::Error(name, 0, "mesh has a non-finite vertex coordinate");
    for (const auto& t : m.triangles)
        if (t[0] >= m.vertices.size() || t[1] >= m.vertices.size() || t[2] >= m.vertices.size())
            throw core::Error(name, 0, "mesh has a triangle with a vertex index out of range");
    const MeshTopology t = analyseTopology(m);
    if (t.boundaryEdges > 0)
        throw core::Error(name, 0,
                          "open mesh (not watertight): " + std::to_string(t.boundaryEdges) +
                              " boundary edges; the volumetric tracer needs a closed surface");
    if (t.nonManifoldEdges > 0)
        throw core::Error(name, 0,
                          "non-manifold mesh: " + std::to_string(t.nonManifoldEdges) +
                              " edges are shared by more than two triangles");
    if (t.inconsistentEdges > 0)
        throw core::Error(name, 0,
                          "inconsistent winding: " + std::to_string(t.inconsistentEdges) +
                              " edges are used twice in the same direction (flipped triangles)");
    if (!(t.signedVolume > 0)) {
        if (t.signedVolume < 0)
            throw core::Error(name, 0,
                              "mesh normals point inward (signed volume < 0): flip the winding");
        throw core::Error(name, 0, "mesh encloses no volume (signed volume 0)");
    }
}

double normalizeMesh(Mesh& m, const std::string& name) {
    if (m.vertices.empty()) throw core::Error(name, 0, "empty mesh: no vertices");
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -lo[a];
    }
    // The bounding box of the vertices the triangles use.
    std::vector<bool> used(m.vertices.size(), m.triangles.empty());
    for (const auto& t : m.triangles)
        for (uint32_t v : t)
            if (v < used.size()) used[v] = true;
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        if (!used[i]) continue;
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(m.vertices[i][static_cast<size_t>(a)]));
            hi[a] = std::max(hi[a], double(m.vertices[i][static_cast<size_t>(a)]));
        }
    }
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(longest > 0) || !std::isfinite(longest))
        throw core::Error(name, 0, "mesh has no extent (all vertices coincide or are not finite)");
    for (auto& v : m.vertices)
        for (int a = 0; a < 3; ++a)
            v[static_cast<size_t>(a)] = static_cast<float>(
                (double(v[static_cast<size_t>(a)]) - 0.5 * (lo[a] + hi[a])) / longest);
    return longest;
}

} // namespace mesh
