// mesh suite (suite.h): every shape of the default suite is closed, manifold, outward and
// encloses the volume its parameters give in closed form; specs are canonical and round-trip;
// bad specs name the shape, the parameter, its value and its range.
#include "core/core.h"
#include "mesh/suite.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace mesh;

namespace {

std::string messageOf(const std::string& spec) {
    try {
        makeSuiteShape(spec, "--shapes");
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

// The enclosed volume in closed form (l_d³), and the relative tolerance of its tessellation.
std::pair<double, double> closedFormVolume(const SuiteShape& s) {
    const auto p = [&](const char* n) {
        for (const auto& [name, v] : s.params)
            if (name == n) return v;
        ADD_FAILURE() << "no parameter " << n;
        return 0.0;
    };
    const double pi = std::numbers::pi;
    if (s.kind == "slab") return {p("w") * p("w") * p("t"), 1e-5};
    if (s.kind == "edge") return {1.25 * std::pow(p("s"), 3), 1e-5};
    if (s.kind == "corner") return {std::pow(p("s"), 3), 1e-5};
    if (s.kind == "fin") return {12 * 3 * 10 + p("t") * p("h") * 10, 1e-5};
    // the 24-segment half circle's area is (n/2) r² sin(2π/2n)·… within 0.3 % of πr²/2
    if (s.kind == "groove") return {(12 * 6 - 0.5 * pi * p("r") * p("r")) * 10, 3e-4};
    const double r = s.kind == "sphere" ? p("r") : 2.0;
    return {4.0 / 3.0 * pi * r * r * r, s.kind == "sphere" ? 2e-3 : 0.7};
}

} // namespace

TEST(Suite, EveryDefaultShapeIsClosedOutwardAndEnclosesItsVolume) {
    const std::vector<std::string> suite = defaultSuite();
    EXPECT_EQ(suite.size(), 25u);
    double previousTessellationError = 1e9;
    for (const std::string& spec : suite) {
        const SuiteShape s = makeSuiteShape(spec, "test");
        EXPECT_EQ(s.spec, spec) << "canonical specs round-trip";
        EXPECT_NO_THROW(checkClosedOutward(s.mesh, spec));
        const MeshTopology t = analyseTopology(s.mesh);
        const auto [volume, tolerance] = closedFormVolume(s);
        EXPECT_NEAR(t.signedVolume / volume, 1.0, tolerance) << spec;
        if (s.kind == "tessellation") { // coarse to fine: the error falls level by level
            const double err = std::abs(t.signedVolume / volume - 1);
            EXPECT_LT(err, previousTessellationError) << spec;
            previousTessellationError = err;
        }
        EXPECT_NEAR(std::hypot(s.light[0], s.light[1], s.light[2]), 1.0, 1e-12) << spec;
        ASSERT_EQ(s.mesh.normals.size(), s.mesh.vertices.size()) << spec;
        double lo = 1e9, hi = -1e9; // centred on the bounding box
        for (const auto& v : s.mesh.vertices) {
            lo = std::min(lo, double(v[2]));
            hi = std::max(hi, double(v[2]));
        }
        EXPECT_NEAR(lo + hi, 0.0, 1e-4 * s.longestAxis) << spec;
        EXPECT_GT(s.longestAxis, 0.0) << spec;
    }
    EXPECT_LT(previousTessellationError, 2e-3);
}

TEST(Suite, FeaturesFaceTheCameraAndTheLightAsDescribed) {
    // the edge: the vertex nearest the camera lies on the 90° edge, whose two faces tilt ±45°
    const SuiteShape edge = makeSuiteShape("edge", "test");
    int towardsCamera = 0, litMore = 0;
    for (size_t i = 0; i < edge.mesh.normals.size(); i += 4) {
        const auto& n = edge.mesh.normals[i];
        if (n[2] > 0.7f && n[2] < 0.71f) {
            ++towardsCamera;
            litMore += n[0] * edge.light[0] + n[1] * edge.light[1] + n[2] * edge.light[2] > 0.9;
        }
    }
    EXPECT_EQ(towardsCamera, 2);
    EXPECT_EQ(litMore, 1);
    // the corner: three faces at equal angles (cos 1/√3) to the view direction
    const SuiteShape corner = makeSuiteShape("corner", "test");
    int faces = 0;
    for (size_t i = 0; i < corner.mesh.normals.size(); i += 4)
        faces += std::abs(corner.mesh.normals[i][2] - 1 / std::sqrt(3.0)) < 1e-5;
    EXPECT_EQ(faces, 3);
    // the back-lit slab: the light comes from behind the face the camera sees
    EXPECT_LT(makeSuiteShape("slab:view=back", "test").light[2], 0);
    EXPECT_GT(makeSuiteShape("slab", "test").light[2], 0);
}

TEST(Suite, SpecsAreCanonical) {
    EXPECT_EQ(makeSuiteShape(" slab : t = 0.30 ", "x").spec, "slab:t=0.3,w=20,view=front");
    EXPECT_EQ(makeSuiteShape("slab:view=back,t=2", "x").spec, "slab:t=2,w=20,view=back");
    EXPECT_EQ(makeSuiteShape("sphere", "x").spec, "sphere:r=2");
    EXPECT_EQ(makeSuiteShape("tessellation:level=6", "x").spec, "tessellation:level=6");
}

TEST(Suite, BadSpecsNameTheParameterItsValueAndItsRange) {
    EXPECT_EQ(messageOf("slab:t=50"),
              "--shapes: slab: t = 50 is out of range [0.05, 20] (thickness, in l_d)");
    EXPECT_EQ(messageOf("sphere:r=0"),
              "--shapes: sphere: r = 0 is out of range [0.1, 50] (radius, in l_d)");
    EXPECT_NE(messageOf("tessellation:level=2.5").find("level must be an integer"),
              std::string::npos);
    EXPECT_NE(messageOf("tessellation:level=7").find("out of range [1, 6]"), std::string::npos);
    EXPECT_NE(messageOf("teapot").find("unknown shape 'teapot' (the suite has: slab, edge"),
              std::string::npos);
    EXPECT_NE(messageOf("slab:q=1").find("no parameter 'q' (it has: t, w, view)"),
              std::string::npos);
    EXPECT_NE(messageOf("slab:t").find("expected NAME=VALUE"), std::string::npos);
    EXPECT_NE(messageOf("slab:t=abc").find("t must be a number, got 'abc'"), std::string::npos);
    EXPECT_NE(messageOf("slab:view=side").find("view must be front or back"), std::string::npos);
    EXPECT_NE(messageOf("groove:r=nan").find("r must be a number"), std::string::npos);
}

TEST(Suite, EarClippingTriangulatesSimplePolygonsAndRejectsOthers) {
    // an L: 6 vertices, 4 triangles, area 3
    const std::vector<std::array<double, 2>> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    const auto tris = triangulatePolygon(l);
    ASSERT_EQ(tris.size(), 4u);
    double area = 0;
    for (const auto& t : tris) {
        const auto &a = l[t[0]], &b = l[t[1]], &c = l[t[2]];
        const double twice = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        EXPECT_GT(twice, 0) << "counter-clockwise";
        area += 0.5 * twice;
    }
    EXPECT_NEAR(area, 3.0, 1e-12);
    // clockwise (or self-intersecting) input has no ear
    EXPECT_THROW(triangulatePolygon({{0, 0}, {0, 1}, {1, 1}, {1, 0}}), core::Error);
    EXPECT_THROW(triangulatePolygon({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), core::Error);
}
