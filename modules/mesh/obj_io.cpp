// mesh/obj_io: OBJ in (tinyobjloader) and out (see mesh.h).
#include "mesh/mesh.h"

#include "core/core.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <tuple>

namespace mesh {
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

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
        s.pop_back();
    return s;
}

} // namespace

Mesh loadObj(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string text = core::readFile(path); // Error(path, 0, ...) when missing
    checkVertexLines(text, name);
    tinyobj::ObjReader reader;
    tinyobj::ObjReaderConfig cfg;
    cfg.triangulate = true;
    cfg.vertex_color = false;
    if (!reader.ParseFromString(text, "", cfg)) {
        const std::string e = trimmed(reader.Error());
        throw core::Error(name, 0,
                          "malformed OBJ: " + (e.empty() ? std::string("parse error") : e));
    }
    const std::string& warn = reader.Warning();
    if (warn.find("out of bounds") != std::string::npos)
        throw core::Error(name, 0, "malformed OBJ: " + trimmed(warn));
    const auto& attrib = reader.GetAttrib();
    const size_t nv = attrib.vertices.size() / 3;
    const size_t nn = attrib.normals.size() / 3;
    const size_t nt = attrib.texcoords.size() / 2;

    // Normals and UVs are kept only when every face corner has one.
    bool allN = true, allUv = true;
    for (const auto& shape : reader.GetShapes())
        for (const auto& idx : shape.mesh.indices) {
            allN = allN && idx.normal_index >= 0 && static_cast<size_t>(idx.normal_index) < nn;
            allUv =
                allUv && idx.texcoord_index >= 0 && static_cast<size_t>(idx.texcoord_index) < nt;
        }

    Mesh m;
    m.vertices.resize(nv);
    for (size_t i = 0; i < nv; ++i)
        m.vertices[i] = {attrib.vertices[3 * i], attrib.vertices[3 * i + 1],
                         attrib.vertices[3 * i + 2]};
    if (allN) m.normals.assign(nv, {0.0f, 0.0f, 1.0f});
    if (allUv) m.uvs.assign(nv, {0.0f, 0.0f});
    // Vertex i of the file is the first (i, normal, uv) triple met; other triples of the same
    // position become new vertices (sharp edges, UV seams).
    std::vector<std::pair<int, int>> claim(nv, {-2, -2});
    std::map<std::tuple<int, int, int>, uint32_t> extra;
    auto vertexOf = [&](int vi, int ni, int ti) -> uint32_t {
        auto& c = claim[static_cast<size_t>(vi)];
        if (c.first == -2 || c == std::pair{ni, ti}) {
            if (c.first == -2) {
                c = {ni, ti};
                if (allN)
                    for (size_t a = 0; a < 3; ++a)
                        m.normals[static_cast<size_t>(vi)][a] =
                            attrib.normals[3 * static_cast<size_t>(ni) + a];
                if (allUv)
                    for (size_t a = 0; a < 2; ++a)
                        m.uvs[static_cast<size_t>(vi)][a] =
                            attrib.texcoords[2 * static_cast<size_t>(ti) + a];
            }
            return static_cast<uint32_t>(vi);
        }
        auto [it, inserted] =
            extra.emplace(std::tuple{vi, ni, ti}, static_cast<uint32_t>(m.vertices.size()));
        if (inserted) {
            m.vertices.push_back(m.vertices[static_cast<size_t>(vi)]);
            if (allN)
                m.normals.push_back({attrib.normals[3 * static_cast<size_t>(ni)],
                                     attrib.normals[3 * static_cast<size_t>(ni) + 1],
                                     attrib.normals[3 * static_cast<size_t>(ni) + 2]});
            if (allUv)
                m.uvs.push_back({attrib.texcoords[2 * static_cast<size_t>(ti)],
                                 attrib.texcoords[2 * static_cast<size_t>(ti) + 1]});
        }
        return it->second;
    };
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
                const auto& idx = shape.mesh.indices[offset + k];
                const int vi = idx.vertex_index;
                if (vi < 0 || static_cast<size_t>(vi) >= nv)
                    throw core::Error(name, 0,
                                      "malformed OBJ: face " + std::to_string(f + 1) +
                                          " of shape '" + shape.name +
                                          "' refers to a missing vertex (" + std::to_string(nv) +
                                          " vertices)");
                t[k] = vertexOf(vi, allN ? idx.normal_index : -1, allUv ? idx.texcoord_index : -1);
            }
            m.triangles.push_back(t);
            offset += fv;
        }
    }
    if (m.triangles.empty())
        throw core::Error(name, 0, "malformed OBJ: no triangles (no 'f' lines)");
    for (auto& n : m.normals) {
        const double len =
            std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
        if (len > 0 && std::isfinite(len) && len != 1.0)
            n = {static_cast<float>(n[0] / len), static_cast<float>(n[1] / len),
                 static_cast<float>(n[2] / len)};
    }
    weldVertices(m);
    if (m.triangles.empty())
        throw core::Error(name, 0, "malformed OBJ: every face repeats a vertex (degenerate)");
    if (!allN) computeVertexNormals(m);
    return m;
}

void writeObj(const std::filesystem::path& path, const Mesh& m) {
    const bool hasN = !m.normals.empty() && m.normals.size() == m.vertices.size();
    const bool hasUv = !m.uvs.empty() && m.uvs.size() == m.vertices.size();
    std::ostringstream out;
    out.precision(9);
    out << "# bssrdf-workbench mesh: " << m.vertices.size() << " vertices, " << m.triangles.size()
        << " triangles\n";
    for (const auto& v : m.vertices)
        out << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    if (hasUv)
        for (const auto& t : m.uvs)
            out << "vt " << t[0] << ' ' << t[1] << '\n';
    if (hasN)
        for (const auto& n : m.normals)
            out << "vn " << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
    for (const auto& t : m.triangles) {
        out << 'f';
        for (uint32_t v : t) {
            out << ' ' << v + 1;
            if (hasUv)
                out << '/' << v + 1;
            else if (hasN)
                out << '/';
            if (hasN) out << '/' << v + 1;
        }
        out << '\n';
    }
    core::writeFile(path, out.str());
}

} // namespace mesh
