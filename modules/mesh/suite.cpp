// mesh/suite: the geometry stress suite's shapes (suite.h).
#include "mesh/suite.h"

#include "core/core.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

namespace mesh {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string g(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

double cross2(const std::array<double, 2>& o, const std::array<double, 2>& a,
              const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Rotation about x by `ax`, then about y by `ay`, then about z by `az` (radians), in place.
void rotate(Mesh& m, double ax, double ay, double az) {
    const auto turn = [&](std::array<float, 3>& v) {
        double x = v[0], y = v[1], z = v[2];
        double t = y * std::cos(ax) - z * std::sin(ax);
        z = y * std::sin(ax) + z * std::cos(ax);
        y = t;
        t = x * std::cos(ay) + z * std::sin(ay);
        z = -x * std::sin(ay) + z * std::cos(ay);
        x = t;
        t = x * std::cos(az) - y * std::sin(az);
        y = x * std::sin(az) + y * std::cos(az);
        x = t;
        v = {float(x), float(y), float(z)};
    };
    for (auto& v : m.vertices)
        turn(v);
    for (auto& n : m.normals)
        turn(n);
}

void scale(Mesh& m, double s) {
    for (auto& v : m.vertices)
        for (float& c : v)
            c = float(c * s);
}

// Centres the bounding box at the origin; returns its longest side.
double centre(Mesh& m) {
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& v : m.vertices)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(v[k]));
            hi[k] = std::max(hi[k], double(v[k]));
        }
    double longest = 0;
    for (int k = 0; k < 3; ++k)
        longest = std::max(longest, hi[k] - lo[k]);
    for (auto& v : m.vertices)
        for (int k = 0; k < 3; ++k)
            v[k] = float(v[k] - 0.5 * (lo[k] + hi[k]));
    return longest;
}

std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return "";
    return s.substr(a, s.find_last_not_of(" \t") + 1 - a);
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    size_t from = 0;
    for (size_t at; (at = s.find(sep, from)) != std::string::npos; from = at + 1)
        out.push_back(s.substr(from, at - from));
    out.push_back(s.substr(from));
    return out;
}

std::array<double, 3> unit(double x, double y, double z) {
    const double n = std::sqrt(x * x + y * y + z * z);
    return {x / n, y / n, z / n};
}

const SuiteKind& kindOf(const std::string& name, const std::string& label) {
    for (const SuiteKind& k : suiteKinds())
        if (name == k.name) return k;
    std::string names;
    for (const SuiteKind& k : suiteKinds())
        names += std::string(names.empty() ? "" : ", ") + k.name;
    throw core::Error(label, 0, "unknown shape '" + name + "' (the suite has: " + names + ")");
}

} // namespace

const std::vector<SuiteKind>& suiteKinds() {
    static const std::vector<SuiteKind> kinds = {
        {"slab",
         "a square slab lit from the front (view=front) or from behind (view=back)",
         {{"t", 0.05, 20, 1, "thickness"}, {"w", 1, 100, 20, "width"}}},
        {"edge", "a 90° edge towards the camera, one face lit more", {{"s", 1, 50, 8, "side"}}},
        {"corner", "a cube corner towards the camera", {{"s", 1, 50, 8, "side"}}},
        {"fin",
         "a thin wall on a block, lit from one side",
         {{"t", 0.05, 4, 0.5, "fin thickness"}, {"h", 0.5, 20, 5, "fin height"}}},
        {"groove",
         "a half-cylinder groove in a 12 x 6 block",
         {{"r", 0.2, 2.8, 2, "groove radius"}}},
        {"sphere", "a sphere (48 rings x 96 segments)", {{"r", 0.1, 50, 2, "radius"}}},
        {"tessellation",
         "the sphere of radius 2 at tessellation levels 1 (4 x 8) to 6 (48 x 96)",
         {{"level", 1, 6, 3, "tessellation level (integer)"}}},
    };
    return kinds;
}

std::vector<std::string> defaultSuite() {
    std::vector<std::string> specs;
    for (const char* view : {"front", "back"})
        for (double t : {0.1, 0.3, 1.0, 3.0, 10.0})
            specs.push_back("slab:t=" + g(t) + ",view=" + view);
    for (const char* k : {"edge", "corner", "fin", "groove"})
        specs.push_back(k);
    for (double r : {0.5, 1.0, 2.0, 5.0, 20.0})
        specs.push_back("sphere:r=" + g(r));
    for (int level = 1; level <= 6; ++level)
        specs.push_back("tessellation:level=" + std::to_string(level));
    for (auto& s : specs)
        s = makeSuiteShape(s, "suite").spec;
    return specs;
}

std::vector<std::array<uint32_t, 3>>
triangulatePolygon(const std::vector<std::array<double, 2>>& p) {
    std::vector<uint32_t> left(p.size());
    for (size_t i = 0; i < p.size(); ++i)
        left[i] = uint32_t(i);
    std::vector<std::array<uint32_t, 3>> tris;
    while (left.size() > 3) {
        bool clipped = false;
        for (size_t i = 0; i < left.size() && !clipped; ++i) {
            const uint32_t a = left[(i + left.size() - 1) % left.size()], b = left[i],
                           c = left[(i + 1) % left.size()];
            if (cross2(p[a], p[b], p[c]) <= 1e-12) continue; // reflex or flat: not an ear
            bool empty = true;
            for (uint32_t q : left) {
                if (q == a || q == b || q == c) continue;
                if (cross2(p[a], p[b], p[q]) >= 0 && cross2(p[b], p[c], p[q]) >= 0 &&
                    cross2(p[c], p[a], p[q]) >= 0) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            tris.push_back({a, b, c});
            left.erase(left.begin() + long(i));
            clipped = true;
        }
        if (!clipped)
            throw core::Error("polygon", 0,
                              "no ear to clip: the profile is not a simple counter-clockwise "
                              "polygon");
    }
    if (left.size() == 3) tris.push_back({left[0], left[1], left[2]});
    // A self-intersecting outline can still be clipped into ears; their areas then exceed its
    // shoelace area (a bow tie has none).
    double polygonArea = 0, trianglesArea = 0;
    for (size_t i = 0; i < p.size(); ++i)
        polygonArea += cross2({0, 0}, p[i], p[(i + 1) % p.size()]);
    for (const auto& t : tris)
        trianglesArea += std::abs(cross2(p[t[0]], p[t[1]], p[t[2]]));
    if (!(std::abs(trianglesArea - polygonArea) <= 1e-9 * trianglesArea))
        throw core::Error("polygon", 0,
                          "the profile is not a simple counter-clockwise polygon (it crosses "
                          "itself)");
    return tris;
}

Mesh extrudeProfile(const std::vector<std::array<double, 2>>& profile, double length) {
    Mesh m;
    const double h = 0.5 * length;
    const auto add = [&](double x, const std::array<double, 2>& q, std::array<float, 3> n) {
        m.vertices.push_back({float(x), float(q[0]), float(q[1])});
        m.normals.push_back(n);
        return uint32_t(m.vertices.size() - 1);
    };
    const auto caps = triangulatePolygon(profile);
    for (int side : {+1, -1}) {
        const uint32_t base = uint32_t(m.vertices.size());
        for (const auto& q : profile)
            add(side * h, q, {float(side), 0.0f, 0.0f});
        for (const auto& t : caps)
            m.triangles.push_back(
                side > 0 ? std::array<uint32_t, 3>{base + t[0], base + t[1], base + t[2]}
                         : std::array<uint32_t, 3>{base + t[0], base + t[2], base + t[1]});
    }
    for (size_t i = 0; i < profile.size(); ++i) {
        const auto& p0 = profile[i];
        const auto& p1 = profile[(i + 1) % profile.size()];
        const double dy = p1[0] - p0[0], dz = p1[1] - p0[1], l = std::hypot(dy, dz);
        const std::array<float, 3> n{0.0f, float(dz / l), float(-dy / l)};
        const uint32_t a = add(-h, p0, n), b = add(-h, p1, n), c = add(h, p1, n), d = add(h, p0, n);
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
    }
    return m;
}

SuiteShape makeSuiteShape(const std::string& specText, const std::string& label) {
    const std::string spec = trim(specText);
    const size_t colon = spec.find(':');
    const SuiteKind& kind = kindOf(trim(spec.substr(0, colon)), label);
    SuiteShape s;
    s.kind = kind.name;
    std::map<std::string, double> values;
    for (const SuiteParam& p : kind.params)
        values[p.name] = p.dflt;
    if (s.kind == "slab") s.view = "front";
    if (colon != std::string::npos) {
        for (const std::string& item : split(spec.substr(colon + 1), ',')) {
            const size_t eq = item.find('=');
            const std::string name = trim(item.substr(0, eq));
            const std::string where = s.kind + ": ";
            if (eq == std::string::npos)
                throw core::Error(label, 0, where + "expected NAME=VALUE, got '" + item + "'");
            const std::string text = trim(item.substr(eq + 1));
            if (s.kind == "slab" && name == "view") {
                if (text != "front" && text != "back")
                    throw core::Error(label, 0,
                                      where + "view must be front or back, got '" + text + "'");
                s.view = text;
                continue;
            }
            const SuiteParam* param = nullptr;
            for (const SuiteParam& p : kind.params)
                if (name == p.name) param = &p;
            if (!param) {
                std::string names;
                for (const SuiteParam& p : kind.params)
                    names += std::string(names.empty() ? "" : ", ") + p.name;
                if (s.kind == "slab") names += ", view";
                throw core::Error(label, 0,
                                  where + "no parameter '" + name + "' (it has: " + names + ")");
            }
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
                throw core::Error(label, 0, where + name + " must be a number, got '" + text + "'");
            if (v < param->lo || v > param->hi)
                throw core::Error(label, 0,
                                  where + name + " = " + g(v) + " is out of range [" +
                                      g(param->lo) + ", " + g(param->hi) + "] (" + param->meaning +
                                      (s.kind == "tessellation" ? "" : ", in l_d") + ")");
            if (s.kind == "tessellation" && v != std::floor(v))
                throw core::Error(label, 0, where + "level must be an integer, got " + g(v));
            values[name] = v;
        }
    }
    s.spec = s.kind;
    for (size_t i = 0; i < kind.params.size(); ++i) {
        const double v = values[kind.params[i].name];
        s.params.emplace_back(kind.params[i].name, v);
        s.spec += (i ? "," : ":") + std::string(kind.params[i].name) + "=" + g(v);
    }
    if (!s.view.empty()) s.spec += ",view=" + s.view;

    const auto v = [&](const char* n) { return values.at(n); };
    if (s.kind == "slab") {
        s.mesh = makeBox(v("w"), v("w"), v("t"));
        s.light = {0, 0, s.view == "front" ? 1.0 : -1.0};
    } else if (s.kind == "edge") {
        s.mesh = makeBox(1.25 * v("s"), v("s"), v("s"));
        rotate(s.mesh, 45 * kDeg, 0, 0); // the +y/+z edge towards the camera
        s.light = unit(0, 0.6, 1);
    } else if (s.kind == "corner") {
        s.mesh = makeBox(v("s"), v("s"), v("s"));
        rotate(s.mesh, 0, 0, -45 * kDeg);                 // (1,1,1) → (√2, 0, 1)
        rotate(s.mesh, 0, -std::atan(std::sqrt(2.0)), 0); // → (0, 0, √3)
        s.light = unit(0.3, 0.4, 1);
    } else if (s.kind == "fin") {
        const double t = v("t"), hgt = v("h");
        s.mesh = extrudeProfile({{-6, 0},
                                 {6, 0},
                                 {6, 3},
                                 {0.5 * t, 3},
                                 {0.5 * t, 3 + hgt},
                                 {-0.5 * t, 3 + hgt},
                                 {-0.5 * t, 3},
                                 {-6, 3}},
                                10);
        rotate(s.mesh, -35 * kDeg, 0, 0); // the fin's lit side and the block's top visible
        s.light = unit(0, -0.8, 0.6);
    } else if (s.kind == "groove") {
        const double r = v("r");
        std::vector<std::array<double, 2>> profile{{-6, 0}, {6, 0}, {6, 6}};
        const int n = 24;
        for (int k = 0; k <= n; ++k) {
            const double phi = std::numbers::pi * k / n;
            profile.push_back({r * std::cos(phi), 6 - r * std::sin(phi)});
        }
        profile.push_back({-6, 6});
        s.mesh = extrudeProfile(profile, 10);
        rotate(s.mesh, -25 * kDeg, 0, 0);
        s.light = unit(0, -0.3, 1);
    } else { // sphere, tessellation
        static const int rings[6] = {4, 6, 8, 12, 24, 48};
        const int level = s.kind == "sphere" ? 6 : int(v("level"));
        s.mesh = makeUvSphere(rings[level - 1], 2 * rings[level - 1]);
        scale(s.mesh, 2 * (s.kind == "sphere" ? v("r") : 2.0));
        s.light = unit(0.5, 0.5, 0.7071); // the Lit spheres panel's default
    }
    s.longestAxis = centre(s.mesh);
    return s;
}

} // namespace mesh
