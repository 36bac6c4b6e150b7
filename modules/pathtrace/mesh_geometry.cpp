// pathtrace/mesh_geometry: OBJ in and out, welding, normalisation, the UV sphere and the
// topology checks (see mesh_geometry.h).
#include "pathtrace/mesh_geometry.h"

#include "core/core.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace pathtrace {
namespace {

// tinyobjloader reads a malformed number as 0 without a word; check the vertex lines first.
void checkVertexLines(const std::string& text, const std::string& name) {
    std::istringstream in(text);
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        const size_t k = line.find_first_not_of(" \t");
        const bool vertexLine = k != std::string::npos && k + 1 < line.size() && line[k] == 'v' &&
                                (line[k + 1] == ' ' || line[k + 1] == '\t');
        if (!vertexLine) continue;
        const char* p = line.c_str() + k + 1;
        for (int i = 0; i < 3; ++i) {
            char* end = nullptr;
            const double v = std::strtod(p, &end);
            if (end == p || !std::isfinite(v))
                throw core::Error(name, lineNo,
                                  "malformed OBJ: vertex line needs three finite numbers: '" +
                                      line + "'");
            p = end;
        }
    }
}

struct EdgeUse {
    uint32_t forward = 0, backward = 0; // uses min→max, max→min
};

} // namespace

void weldVertices(Mesh& m) {
    struct Key {
        uint32_t b[3];
        bool operator==(const Key& o) const {
            return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2];
        }
    };
    struct Hash {
        size_t operator()(const Key& k) const {
            uint64_t h = 1469598103934665603ull;
            for (uint32_t v : k.b)
                h = (h ^ v) * 1099511628211ull;
            return static_cast<size_t>(h);
        }
    };
    std::unordered_map<Key, uint32_t, Hash> index;
    std::vector<uint32_t> remap(m.vertices.size());
    std::vector<std::array<float, 3>> out;
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        Key k;
        for (int a = 0; a < 3; ++a) {
            float f = m.vertices[i][static_cast<size_t>(a)];
            if (f == 0.0f) f = 0.0f; // −0 and +0 weld
            std::memcpy(&k.b[a], &f, sizeof f);
        }
        auto [it, inserted] = index.emplace(k, static_cast<uint32_t>(out.size()));
        if (inserted) out.push_back(m.vertices[i]);
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
}

Mesh loadObj(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string text = core::readFile(path); // Error(path, 0, ...) when missing
    checkVertexLines(text, name);
    tinyobj::ObjReader reader;
    tinyobj::ObjReaderConfig cfg;
    cfg.triangulate = true;
    cfg.vertex_color = false;
    if (!reader.ParseFromString(text, "", cfg)) {
        std::string e = reader.Error();
        while (!e.empty() && (e.back() == '\n' || e.back() == '\r'))
            e.pop_back();
        throw core::Error(name, 0,
                          "malformed OBJ: " + (e.empty() ? std::string("parse error") : e));
    }
    const std::string& warn = reader.Warning();
    if (warn.find("out of bounds") != std::string::npos) {
        std::string w = warn;
        while (!w.empty() && (w.back() == '\n' || w.back() == '\r'))
            w.pop_back();
        throw core::Error(name, 0, "malformed OBJ: " + w);
    }
    const auto& attrib = reader.GetAttrib();
    Mesh m;
    const size_t nv = attrib.vertices.size() / 3;
    m.vertices.resize(nv);
    for (size_t i = 0; i < nv; ++i)
        m.vertices[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1],
                         attrib.vertices[3 * i + 2]};
    for (const auto& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const size_t fv = shape.mesh.num_face_vertices[f];
            if (fv != 3)
                throw core::Error(name, 0,
                                  "malformed OBJ: face " + std::to_string(f + 1) + " of shape '" +
                                      shape.name + "' has " + std::to_string(fv) +
                                      " vertices after triangulation");
            std::array<uint32_t, 3> t{};
            for (size_t k = 0; k < 3; ++k) {
                const int vi = shape.mesh.indices[offset + k].vertex_index;
                if (vi < 0 || static_cast<size_t>(vi) >= nv)
                    throw core::Error(name, 0,
                                      "malformed OBJ: face " + std::to_string(f + 1) +
                                          " of shape '" + shape.name +
                                          "' refers to a missing vertex (" + std::to_string(nv) +
                                          " vertices)");
                t[k] = static_cast<uint32_t>(vi);
            }
            m.triangles.push_back(t);
            offset += fv;
        }
    }
    if (m.triangles.empty())
        throw core::Error(name, 0, "malformed OBJ: no triangles (no 'f' lines)");
    weldVertices(m);
    if (m.triangles.empty())
        throw core::Error(name, 0, "malformed OBJ: every face repeats a vertex (degenerate)");
    return m;
}

void writeObj(const std::filesystem::path& path, const Mesh& m) {
    std::ostringstream out;
    out.precision(9);
    out << "# bssrdf-workbench mesh: " << m.vertices.size() << " vertices, " << m.triangles.size()
        << " triangles\n";
    for (const auto& v : m.vertices)
        out << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    for (const auto& t : m.triangles)
        out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    core::writeFile(path, out.str());
}

Mesh makeUvSphere(int rings, int segments) {
    if (rings < 2 || segments < 3)
        throw core::Error("uv sphere", 0,
                          "needs rings >= 2 and segments >= 3, got " + std::to_string(rings) +
                              " x " + std::to_string(segments));
    Mesh m;
    const double r = 0.5;
    m.vertices.push_back({0.0f, 0.0f, static_cast<float>(r)}); // north pole (index 0)
    for (int i = 1; i < rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            m.vertices.push_back({static_cast<float>(r * std::sin(theta) * std::cos(phi)),
                                  static_cast<float>(r * std::sin(theta) * std::sin(phi)),
                                  static_cast<float>(r * std::cos(theta))});
        }
    }
    const uint32_t south = static_cast<uint32_t>(m.vertices.size());
    m.vertices.push_back({0.0f, 0.0f, static_cast<float>(-r)});
    auto ring = [&](int i, int j) { // vertex j of ring i (1 <= i < rings)
        return static_cast<uint32_t>(1 + (i - 1) * segments + (j % segments));
    };
    for (int j = 0; j < segments; ++j) {
        m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i + 1 < rings; ++i) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
        m.triangles.push_back({ring(rings - 1, j), south, ring(rings - 1, j + 1)});
    }
    return m;
}

MeshTopology analyseTopology(const Mesh& m) {
    MeshTopology t;
    std::unordered_map<uint64_t, EdgeUse> edges;
    edges.reserve(m.triangles.size() * 2);
    double vol = 0.0;
    for (const auto& tri : m.triangles) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[static_cast<size_t>(k)],
                           b = tri[static_cast<size_t>((k + 1) % 3)];
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

} // namespace pathtrace
