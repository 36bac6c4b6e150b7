// Tests of the point-cloud renderer (modules/render; thesis 2.6.4, 3.3.3, 3.6.4): camera and
// G-buffer geometry, ε = 0 hierarchical = brute force, the GPU traversal against its CPU
// replica (octree::traverse + octree::accumulate with BSSRDF values from render_pairs.comp),
// with one-point and second-order nodes, error vs ε and criterion, the second-order rule's
// error reduction, the radial profile table, the flat-plate closed form
// M = E·R_dr of the classical dipole, the stack/iteration flags, and keep-last-good models.
#include "render/frame_analysis.h"
#include "render/raster_rule.h"
#include "render/render.h"

#include "../support/dipole_closed_form.h"
#include "../support/gl_fixture.h"
#include "bssrdf/bssrdf.h"
#include "core/core.h"
#include "mesh/mesh.h"
#include "octree/octree.h"
#include "pathtrace/mesh_scene.h"
#include "pointcloud/pointcloud.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

namespace {

namespace fs = std::filesystem;

// Skin-like dipole material (1/mm) on a bunny 50 mm long.
bssrdf::Builtins skin() {
    bssrdf::Builtins b;
    b.sigmaA = {0.032f, 0.17f, 0.48f};
    b.sigmaS = {0.74f, 0.88f, 1.01f};
    b.g = 0.0f;
    b.ior = 1.3f;
    b.scale = 50.0f;
    return b;
}

const glm::vec3 kLight = glm::normalize(glm::vec3(0.4f, 0.8f, 0.45f));

glm::vec3 irradianceOf(const glm::vec3& n) {
    const float c = std::max(0.0f, glm::dot(n, kLight));
    return glm::vec3(1.0f, 0.9f, 0.8f) * c;
}

struct Scene {
    mesh::Mesh mesh;
    octree::Octree tree;
};

Scene makeScene(const mesh::Mesh& m, size_t points, uint64_t seed) {
    Scene s;
    s.mesh = m;
    const pointcloud::PointCloud pc = pointcloud::sampleUniform(m, points, seed);
    std::vector<glm::vec3> p, n, e;
    std::vector<float> a;
    for (const auto& q : pc.points) {
        p.emplace_back(q.p[0], q.p[1], q.p[2]);
        n.emplace_back(q.n[0], q.n[1], q.n[2]);
        a.push_back(q.area);
        e.push_back(irradianceOf(n.back()));
    }
    s.tree = octree::build(p, n, a);
    octree::setIrradiance(s.tree, e);
    return s;
}

const Scene& bunny() {
    static const Scene s = [] {
        mesh::Mesh m = mesh::loadObj(testsupport::sourceRoot() / "third_party/bunny/bunny.obj");
        mesh::normalizeMesh(m, "bunny");
        return makeScene(m, 3000, 5);
    }();
    return s;
}

struct Fixture {
    fs::path root;
    bssrdf::Model dipole, better;
    std::unique_ptr<render::Renderer> renderer;
};

Fixture& fixture() {
    static Fixture f = [] {
        testsupport::context();
        Fixture x;
        x.root = testsupport::makeProjectRoot("render", {"dipole.bssrdf", "better_dipole.bssrdf"});
        x.dipole = bssrdf::loadModel(x.root / "materials/dipole.bssrdf", "materials/dipole.bssrdf");
        x.better = bssrdf::loadModel(x.root / "materials/better_dipole.bssrdf",
                                     "materials/better_dipole.bssrdf");
        x.renderer = std::make_unique<render::Renderer>(shader::Sources{x.root});
        return x;
    }();
    testsupport::context();
    return f;
}

// The renderer set up on the bunny with the dipole and the skin material.
render::Renderer& bunnyRenderer() {
    Fixture& f = fixture();
    f.renderer->setMesh(bunny().mesh);
    f.renderer->setOctree(bunny().tree);
    f.renderer->setModel(f.dipole);
    f.renderer->setMaterial(bssrdf::defaultValues(f.dipole), skin());
    return *f.renderer;
}

render::Settings smallSettings(const mesh::Mesh& m) {
    render::Settings s;
    s.width = 64;
    s.height = 48;
    s.camera.aspect = 64.0f / 48.0f;
    s.camera.yaw = 0.5f;
    s.camera.pitch = 0.3f;
    s.camera.fit(m);
    return s;
}

std::vector<size_t> hitPixels(const render::Readback& r) {
    std::vector<size_t> hits;
    for (size_t p = 0; p < r.position.size(); ++p)
        if (r.position[p].w == 1.0f) hits.push_back(p);
    return hits;
}

// Relative RMS difference of M over the hit pixels: sqrt(Σ|M − R|² / Σ|R|²).
double relativeRms(const render::Readback& a, const render::Readback& ref) {
    double num = 0, den = 0;
    for (size_t p : hitPixels(ref))
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.exitance[p][c]) - double(ref.exitance[p][c]);
            num += d * d;
            den += double(ref.exitance[p][c]) * double(ref.exitance[p][c]);
        }
    return std::sqrt(num / den);
}

} // namespace

TEST(RenderCamera, FitFramesEveryVertex) {
    mesh::Mesh m = bunny().mesh;
    for (float yaw : {0.0f, 1.0f, 2.5f})
        for (float aspect : {0.5f, 1.0f, 2.0f}) {
            render::Camera c;
            c.yaw = yaw;
            c.pitch = 0.4f;
            c.aspect = aspect;
            c.fit(m);
            const glm::mat4 vp = c.projection() * c.view();
            float extent = 0.0f;
            for (const auto& v : m.vertices) {
                const glm::vec4 q = vp * glm::vec4(v[0], v[1], v[2], 1.0f);
                ASSERT_GT(q.w, 0.0f);
                EXPECT_LT(std::fabs(q.x / q.w), 1.0f);
                EXPECT_LT(std::fabs(q.y / q.w), 1.0f);
                EXPECT_GT(q.z / q.w, -1.0f);
                EXPECT_LT(q.z / q.w, 1.0f);
                extent = std::max({extent, std::fabs(q.x / q.w), std::fabs(q.y / q.w)});
            }
            EXPECT_GT(extent, 0.5f) << "the mesh should fill a good part of the view";
        }
}

// G-buffer on a UV sphere of radius 0.5 seen from +z: hits lie on the sphere (up to the
// faceting), normals are unit and close to the radial direction, the image is upright (row 0
// at the top: the top rows see the +y half) and a resize gives the same surface.
TEST(RenderGBuffer, SphereGeometryAndResize) {
    Fixture& f = fixture();
    const mesh::Mesh sphere = mesh::makeUvSphere(48, 96);
    const Scene scene = makeScene(sphere, 500, 3);
    f.renderer->setMesh(scene.mesh);
    f.renderer->setOctree(scene.tree);
    f.renderer->setModel(f.dipole);
    f.renderer->setMaterial(bssrdf::defaultValues(f.dipole), skin());
    render::Settings s;
    s.width = 48;
    s.height = 32;
    s.camera.aspect = 1.5f;
    s.camera.fit(sphere);
    s.bruteForce = true;
    for (int pass = 0; pass < 2; ++pass) {
        f.renderer->render(s);
        const render::Readback r = f.renderer->readback();
        ASSERT_EQ(r.width, s.width);
        ASSERT_EQ(r.height, s.height);
        size_t hits = 0;
        for (int y = 0; y < r.height; ++y)
            for (int x = 0; x < r.width; ++x) {
                const size_t p = r.index(x, y);
                const glm::vec4 pos = r.position[p];
                if (pos.w == 0.0f) {
                    EXPECT_EQ(r.hdr[p].w, 0.0f);
                    continue;
                }
                ++hits;
                const float radius = glm::length(glm::vec3(pos));
                EXPECT_NEAR(radius, 0.5f, 2e-3f);
                const glm::vec3 n = glm::vec3(r.normal[p]);
                EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
                EXPECT_GT(glm::dot(n, glm::vec3(pos) / radius), 0.999f);
                EXPECT_GT(pos.z, -0.05f) << "visible side faces the camera on +z";
                if (y < r.height / 2 - 1) {
                    EXPECT_GT(pos.y, 0.0f) << "row 0 is the top";
                }
                if (y > r.height / 2) {
                    EXPECT_LT(pos.y, 0.0f);
                }
                EXPECT_EQ(r.hdr[p].w, 1.0f);
                EXPECT_GT(r.exitance[p].x, 0.0f);
            }
        // projected disc: π R'² of the image area, R' the silhouette radius in pixels
        EXPECT_GT(hits, size_t(0.25 * s.width * s.height));
        EXPECT_EQ(r.position[r.index(0, 0)].w, 0.0f);
        EXPECT_EQ(r.ldr[4 * r.index(0, 0)],
                  static_cast<unsigned char>(std::lround(s.background.x * 255.0f)));
        s.width /= 2; // half resolution while interacting
        s.height /= 2;
    }
}

// With ε = 0 no interior node is ever accepted (A_v < 0·d2 is false), so the traversal adds
// every point exactly once, the same terms as brute force in another order. Both sums are of
// positive terms: |Ŝ_h − Ŝ_b| <= 2(N − 1)u·S (u = 2^-24) is the rigorous bound; the RMS of the
// relative difference over pixels must be far below it, at the random-walk scale 10·√N·u.
TEST(RenderTraversal, EpsZeroEqualsBruteForce) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.bruteForce = true;
    r.render(s);
    const render::Readback brute = r.readback();
    s.bruteForce = false;
    s.eps = 0.0f;
    r.render(s);
    const render::Readback hier = r.readback();
    const auto hits = hitPixels(brute);
    ASSERT_GT(hits.size(), 300u);
    const double n = double(bunny().tree.points.size());
    const double u = std::ldexp(1.0, -24);
    double sq = 0.0, worst = 0.0;
    for (size_t p : hits) {
        EXPECT_EQ(brute.stats[p].w, uint32_t(n));
        EXPECT_EQ(hier.stats[p].w, uint32_t(n));
        EXPECT_EQ(hier.stats[p].z, 0u);
        EXPECT_EQ(brute.stats[p].x, 0u) << "brute force takes no traversal steps";
        for (int c = 0; c < 3; ++c) {
            const double b = brute.exitance[p][c], h = hier.exitance[p][c];
            ASSERT_GT(b, 0.0);
            const double rel = std::fabs(h - b) / b;
            EXPECT_LE(rel, 2.0 * (n - 1.0) * u);
            sq += rel * rel;
            worst = std::max(worst, rel);
        }
    }
    const double rms = std::sqrt(sq / (3.0 * double(hits.size())));
    std::printf("eps=0 vs brute force: %zu pixels, N=%.0f, rms rel %.3g, max rel %.3g\n",
                hits.size(), n, rms, worst);
    EXPECT_LE(rms, 10.0 * std::sqrt(n) * u);
}

// Splitting the traversal into many short dispatches (each pixel saves its stack, cursor,
// statistics and partial sum, and resumes) changes nothing: bitwise equal results — also
// with direct evaluation, where a second-order node's three terms take three iterations.
TEST(RenderTraversal, ResumedDispatchesAreBitwiseEqual) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    for (int pass = 0; pass < 3; ++pass) {
        const bool brute = pass == 1;
        s.bruteForce = brute;
        s.directBssrdf = pass == 2;
        s.eps = 0.05f;
        s.iterationsPerDispatch = 0;
        const render::Frame one = r.render(s);
        const render::Readback a = r.readback();
        s.iterationsPerDispatch = 37;
        const render::Frame many = r.render(s);
        const render::Readback b = r.readback();
        std::printf("brute=%d direct=%d: %d dispatch(es) of %u vs %d of %u iterations\n",
                    int(brute), int(s.directBssrdf), one.dispatches, one.iterationsPerDispatch,
                    many.dispatches, many.iterationsPerDispatch);
        EXPECT_EQ(one.dispatches, 1);
        EXPECT_GT(many.dispatches, 20);
        for (size_t p = 0; p < a.exitance.size(); ++p) {
            ASSERT_EQ(a.exitance[p], b.exitance[p]) << p;
            ASSERT_EQ(a.stats[p], b.stats[p]) << p;
            ASSERT_EQ(a.hdr[p], b.hdr[p]) << p;
        }
    }
}

// A frame whose traversal state exceeds the storage block limit runs in bands of rows (each
// band's blocks bound on their own, octree_render.comp, Bands) and gives the frame of one band bit
// for bit, resumed across dispatches or not; an odd size leaves a short last band.
TEST(RenderTraversal, BandsOfRowsWithinTheStorageBlockLimitAreBitwiseEqual) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.width = 61;
    s.height = 47;
    s.camera.aspect = 61.0f / 47.0f;
    s.eps = 0.05f;
    for (const uint32_t perDispatch : {0u, 37u}) {
        s.iterationsPerDispatch = perDispatch;
        r.setStorageBlockLimit(0);
        const render::Frame whole = r.render(s);
        const render::Readback a = r.readback();
        r.setStorageBlockLimit(int64_t(s.width) * 96 * 12); // the state of 12 rows
        const render::Frame banded = r.render(s);
        const render::Readback b = r.readback();
        r.setStorageBlockLimit(0);
        std::printf("%u iterations a dispatch: %d band(s), %d dispatch(es) vs %d bands, %d\n",
                    perDispatch, whole.bands, whole.dispatches, banded.bands, banded.dispatches);
        EXPECT_EQ(whole.bands, 1);
        EXPECT_GE(banded.bands, 3);
        EXPECT_GE(banded.dispatches, banded.bands);
        ASSERT_EQ(a.exitance.size(), size_t(61 * 47));
        ASSERT_EQ(b.exitance.size(), a.exitance.size());
        ASSERT_GT(hitPixels(a).size(), 300u);
        for (size_t p = 0; p < a.exitance.size(); ++p) {
            ASSERT_EQ(a.exitance[p], b.exitance[p]) << p;
            ASSERT_EQ(a.stats[p], b.stats[p]) << p;
            ASSERT_EQ(a.hdr[p], b.hdr[p]) << p;
        }
        EXPECT_EQ(a.ldr, b.ldr);
    }
}

namespace {

struct ReplicaResult {
    size_t compared = 0, excluded = 0;
    double worstRel = 0;
};

// Runs the CPU replica for every hit pixel of `gpu` and compares exitance and statistics.
ReplicaResult compareWithReplica(render::Renderer& r, const render::Settings& s,
                                 const render::Readback& gpu, const octree::Octree& tree) {
    ReplicaResult res;
    const octree::Criterion crit = s.criterion();
    const float scale = r.builtins().scale;
    std::vector<octree::Trace> traces;
    std::vector<size_t> pixels;
    std::vector<render::BssrdfPair> pairs;
    for (size_t p : hitPixels(gpu)) {
        octree::Trace t =
            octree::traverse(tree, glm::vec3(gpu.position[p]), glm::vec3(gpu.normal[p]), crit);
        if (t.closestMargin < 1e-5f) {
            ++res.excluded;
            continue;
        }
        const auto tp = render::tracePairs(t, scale);
        pairs.insert(pairs.end(), tp.begin(), tp.end());
        traces.push_back(std::move(t));
        pixels.push_back(p);
    }
    const std::vector<glm::vec3> values = r.evaluatePairs(pairs);
    size_t offset = 0;
    for (size_t i = 0; i < traces.size(); ++i) {
        octree::Trace& t = traces[i];
        const size_t p = pixels[i];
        std::vector<glm::vec3> v(values.begin() + long(offset),
                                 values.begin() + long(offset + t.evaluations.size()));
        offset += t.evaluations.size();
        octree::accumulate(t, v, scale);
        const glm::uvec4 st = gpu.stats[p];
        EXPECT_EQ(st.x, uint32_t(t.steps.size())) << "pixel " << p;
        EXPECT_EQ(st.y, t.maxStackDepth) << "pixel " << p;
        EXPECT_EQ(st.z, t.flags) << "pixel " << p;
        EXPECT_EQ(st.w, uint32_t(t.evaluations.size())) << "pixel " << p;
        for (int c = 0; c < 3; ++c) {
            const double cpu = t.radiantExitance[c], g = gpu.exitance[p][c];
            const double rel = std::fabs(cpu - g) / std::max(std::fabs(cpu), 1e-30);
            res.worstRel = std::max(res.worstRel, rel);
            EXPECT_LE(rel, 1e-5) << "pixel " << p << " channel " << c << " cpu " << cpu << " gpu "
                                 << g;
        }
        ++res.compared;
    }
    return res;
}

} // namespace

// The GPU traversal is the CPU replica: same steps, stack depth, flags and evaluation counts,
// and the same radiant exitance up to float rounding of the BSSRDF evaluation (1e-5
// relative), for both criteria and several ε. Pixels whose traversal met a criterion test
// within 1e-5 of its threshold (Trace::closestMargin) may decide differently and are excluded.
TEST(RenderTraversal, MatchesCpuReplica) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.directBssrdf = true; // the replica's values come from Bssrdf() itself
    for (bool second : {false, true})
        for (bool bbox : {false, true})
            for (float eps : {0.02f, 0.1f, 0.5f}) {
                SCOPED_TRACE("second-order " + std::to_string(second) + " bbox " +
                             std::to_string(bbox) + " eps " + std::to_string(eps));
                s.secondOrder = second;
                s.boundingBoxCriterion = bbox;
                s.eps = eps;
                r.render(s);
                const render::Readback gpu = r.readback();
                const ReplicaResult res = compareWithReplica(r, s, gpu, bunny().tree);
                std::printf("replica second-order=%d bbox=%d eps=%.2f: %zu pixels compared, %zu "
                            "excluded, worst rel %.3g\n",
                            int(second), int(bbox), double(eps), res.compared, res.excluded,
                            res.worstRel);
                EXPECT_GT(res.compared, 300u);
                EXPECT_LE(res.excluded * 50, res.compared) << "at most 2 % excluded";
            }
}

// The second-order cluster rule (octree.h) on the GPU: at equal ε and for both criteria the
// error against brute force is far below that of one-point nodes (the kernel is convex, so
// one point at the mean underestimates every cluster), with the same traversal (same steps)
// and three evaluations per accepted node.
TEST(RenderTraversal, SecondOrderReducesError) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.bruteForce = true;
    r.render(s);
    const render::Readback brute = r.readback();
    s.bruteForce = false;
    for (int bbox = 0; bbox < 2; ++bbox)
        for (float eps : {0.8f, 0.2f}) {
            s.eps = eps;
            s.boundingBoxCriterion = bbox != 0;
            s.secondOrder = false;
            r.render(s);
            const render::Readback one = r.readback();
            s.secondOrder = true;
            r.render(s);
            const render::Readback two = r.readback();
            const double errOne = relativeRms(one, brute), errTwo = relativeRms(two, brute);
            std::printf("eps=%.2f bbox=%d: rel RMS one-point %.4g, second-order %.4g\n",
                        double(eps), bbox, errOne, errTwo);
            // Solid-angle ε = 0.8 accepts clusters wider than the skin kernel's decay length
            // 1/σ_tr (≈ 0.7 mm in blue) next to the receiver, where no low-order expansion
            // converges: there the rule must still help, elsewhere by far more.
            if (bbox == 0 && eps > 0.5f) {
                EXPECT_LT(errTwo, errOne);
            } else {
                EXPECT_LT(errTwo, 0.5 * errOne) << "eps " << eps << " bbox " << bbox;
            }
            size_t nodeEvaluations = 0;
            for (size_t p : hitPixels(brute)) {
                ASSERT_EQ(one.stats[p].x, two.stats[p].x) << "same steps";
                ASSERT_EQ(one.stats[p].y, two.stats[p].y);
                ASSERT_GE(two.stats[p].w, one.stats[p].w);
                const uint32_t extra = two.stats[p].w - one.stats[p].w;
                ASSERT_EQ(extra % 2u, 0u) << "two more evaluations per accepted node";
                nodeEvaluations += extra / 2u;
            }
            EXPECT_GT(nodeEvaluations, 0u);
        }
}

// Flags: a tiny step budget stops every pixel with kFlagIterationCap after exactly maxSteps
// steps; a one-entry stack overflows on pixels that need to push twice. Both agree with the
// replica given the same limits.
TEST(RenderTraversal, StackOverflowAndIterationCapFlags) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.directBssrdf = true;
    s.eps = 0.05f;
    s.maxSteps = 7;
    r.render(s);
    render::Readback gpu = r.readback();
    for (size_t p : hitPixels(gpu)) {
        EXPECT_EQ(gpu.stats[p].x, 7u);
        EXPECT_TRUE(gpu.stats[p].z & octree::kFlagIterationCap);
    }
    compareWithReplica(r, s, gpu, bunny().tree);

    s.maxSteps = octree::kDefaultMaxSteps;
    s.stackSize = 1;
    r.render(s);
    gpu = r.readback();
    size_t overflow = 0;
    for (size_t p : hitPixels(gpu)) {
        EXPECT_LE(gpu.stats[p].y, 1u);
        if (gpu.stats[p].z & octree::kFlagStackOverflow) ++overflow;
    }
    EXPECT_GT(overflow, 0u);
    compareWithReplica(r, s, gpu, bunny().tree);
}

// Error against brute force falls as ε falls; the bounding-box criterion (never farther than
// the nearest point) is at least as accurate as the mean-position one at equal ε. Below the
// float floor — the RMS difference of ε = 0 (every point, another summation order) from brute
// force — differences are rounding, so comparisons allow that floor.
TEST(RenderTraversal, ErrorDecreasesWithEps) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    s.bruteForce = true;
    r.render(s);
    const render::Readback brute = r.readback();
    s.bruteForce = false;
    s.eps = 0.0f;
    r.render(s);
    const double floor = relativeRms(r.readback(), brute);
    std::printf("float floor (eps = 0): rel RMS %.3g\n", floor);
    double previous[2] = {1e30, 1e30};
    for (float eps : {0.8f, 0.2f, 0.05f, 0.0125f}) {
        double err[2];
        double evals[2];
        for (int bbox = 0; bbox < 2; ++bbox) {
            s.eps = eps;
            s.boundingBoxCriterion = bbox != 0;
            r.render(s);
            const render::Readback h = r.readback();
            err[bbox] = relativeRms(h, brute);
            double e = 0;
            for (size_t p : hitPixels(h))
                e += h.stats[p].w;
            evals[bbox] = e / double(hitPixels(h).size());
            EXPECT_LT(err[bbox], std::max(previous[bbox], 2.0 * floor))
                << "eps " << eps << " bbox " << bbox;
            previous[bbox] = err[bbox];
        }
        std::printf("eps=%.4f: rel RMS default %.3g (%.0f evals/pixel), bbox %.3g (%.0f)\n",
                    double(eps), err[0], evals[0], err[1], evals[1]);
        EXPECT_LE(err[1], err[0] + floor) << "eps " << eps;
    }
}

// The profile table of a radial model against Bssrdf() itself: (1) the table at random radii
// in [0, rMax) vs render_pairs.comp, relative 1e-3 wherever R_c(r) >= 1e-6·R_c(0);
// (2) whole renders with the table vs direct evaluation, relative 1e-3 per pixel.
TEST(RenderProfileTable, AgreesWithDirectBssrdf) {
    Fixture& f = fixture();
    render::Renderer& r = bunnyRenderer();
    for (const bssrdf::Model* model : {&f.dipole, &f.better}) {
        SCOPED_TRACE(model->path);
        r.setModel(*model);
        r.setMaterial(bssrdf::defaultValues(*model), skin());
        render::Settings s = smallSettings(bunny().mesh);
        s.eps = 0.05f;
        r.render(s);
        const render::Readback table = r.readback();
        const render::ProfileTable& t = r.profileTable();
        ASSERT_EQ(t.values.size(), size_t(render::kProfileEntries));
        ASSERT_GT(t.rMax, 0.0f);
        std::printf("%s: rMax %.4g mm\n", model->path.c_str(), double(t.rMax));

        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        const glm::vec3 n(0.0f, 0.0f, 1.0f);
        std::vector<render::BssrdfPair> pairs{{glm::vec3(0.0f), n, glm::vec3(0.0f), n}};
        std::vector<float> radii{0.0f};
        for (int i = 0; i < 4000; ++i) {
            const float q = u(rng);
            const float rr = t.rMax * q * q * 0.9999f;
            radii.push_back(rr);
            pairs.push_back({glm::vec3(0.0f), n, glm::vec3(rr, 0.0f, 0.0f), n});
        }
        const std::vector<glm::vec3> direct = r.evaluatePairs(pairs);
        double worst = 0;
        size_t checked = 0;
        for (size_t i = 0; i < radii.size(); ++i) {
            const glm::vec3 tab = render::lookupProfile(t, radii[i]);
            for (int c = 0; c < 3; ++c) {
                if (direct[i][c] < 1e-6f * direct[0][c]) continue;
                const double rel = std::fabs(double(tab[c]) - direct[i][c]) / direct[i][c];
                worst = std::max(worst, rel);
                ++checked;
                EXPECT_LE(rel, 1e-3) << "r " << radii[i] << " channel " << c;
            }
        }
        std::printf("  table vs direct: %zu values, worst rel %.3g\n", checked, worst);
        EXPECT_GT(checked, 3000u);

        s.directBssrdf = true;
        r.render(s);
        const render::Readback dir = r.readback();
        double worstPixel = 0;
        for (size_t p : hitPixels(dir)) {
            EXPECT_EQ(dir.stats[p], table.stats[p]);
            for (int c = 0; c < 3; ++c) {
                const double rel = std::fabs(double(table.exitance[p][c]) - dir.exitance[p][c]) /
                                   dir.exitance[p][c];
                worstPixel = std::max(worstPixel, rel);
                EXPECT_LE(rel, 1e-3);
            }
        }
        std::printf("  renders table vs direct: worst pixel rel %.3g\n", worstPixel);
    }
}

// Closed form: a plate lit uniformly (E per point) has M = E·∫R_d dA = E·R_dr far from its
// edges, R_dr = α'/2·(1 + e^(−4/3·A·√(3(1−α'))))·e^(−√(3(1−α'))) for the classical dipole
// (materials/dipole.bssrdf, its DiffuseReflectance section; computed here in double).
// Points: a square grid of spacing h = 0.6·z_r on the top face, area h² each. The midpoint
// rule of a smooth, decaying integrand errs by its Fourier transform at 2π/h (Poisson
// summation), ~ 4·e^(−2π·z_r/h) ≈ 1e-4 here; the truncation at ρ = 12/σ_tr from the receiver
// loses < 1e-5; float sums of ~24k positive terms < 1e-5. Bound used: 1e-3 relative.
TEST(RenderClosedForm, PlateExitanceIsDiffuseReflectance) {
    Fixture& f = fixture();
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(0.1f, 0.05f, 0.2f);
    b.sigmaS = glm::vec3(1.0f, 1.5f, 1.0f);
    b.ior = 1.3f;
    b.scale = 1.0f; // mesh units are mm
    const float thickness = 1.0f, half = 30.0f;
    const mesh::Mesh plate = mesh::makeThinPlate(2.0 * half, 2.0 * half, thickness);
    double zrMin = 1e30, sigmaTrMin = 1e30;
    for (int c = 0; c < 3; ++c) {
        const double st = double(b.sigmaA[c]) + double(b.sigmaS[c]);
        zrMin = std::min(zrMin, 1.0 / st);
        sigmaTrMin = std::min(sigmaTrMin, std::sqrt(3.0 * b.sigmaA[c] * st));
    }
    ASSERT_LT(12.0 / sigmaTrMin, half - 5.0) << "the plate must hold the profile";
    const float h = float(0.6 * zrMin);
    const int k = int(std::floor(2.0f * half / h));
    const glm::vec3 e(1.0f, 2.0f, 0.5f);
    std::vector<glm::vec3> p, n, irr;
    std::vector<float> a;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            p.emplace_back(-half + (float(i) + 0.5f) * h, -half + (float(j) + 0.5f) * h,
                           0.5f * thickness);
            n.emplace_back(0.0f, 0.0f, 1.0f);
            a.push_back(h * h);
            irr.push_back(e);
        }
    octree::Octree tree = octree::build(p, n, a);
    octree::setIrradiance(tree, irr);
    f.renderer->setMesh(plate);
    f.renderer->setOctree(tree);
    f.renderer->setModel(f.dipole);
    f.renderer->setMaterial(bssrdf::defaultValues(f.dipole), b);
    render::Settings s;
    s.width = s.height = 8;
    s.camera.target = glm::vec3(0.0f, 0.0f, 0.5f * thickness);
    s.camera.yaw = 0.0f; // camera on +z, looking down at the lit face
    s.camera.pitch = 0.0f;
    s.camera.distance = 20.0f;
    s.camera.radius = 45.0f;
    s.camera.fovY = 0.3f;
    s.bruteForce = true;
    s.directBssrdf = true;
    f.renderer->render(s);
    const render::Readback rb = f.renderer->readback();
    const size_t centre = rb.index(4, 4);
    ASSERT_EQ(rb.position[centre].w, 1.0f);
    const glm::vec3 xo(rb.position[centre]);
    ASSERT_LT(std::max(std::fabs(xo.x), std::fabs(xo.y)), 3.0f);
    ASSERT_NEAR(xo.z, 0.5f * thickness, 1e-5f);

    const double ior = b.ior;
    for (int c = 0; c < 3; ++c) {
        const testsupport::ClassicalDipole d{double(b.sigmaA[c]), double(b.sigmaS[c]), ior};
        const double expected = double(e[c]) * d.rdr();
        const double got = rb.exitance[centre][c];
        std::printf("plate channel %d: M %.7g, E·R_dr %.7g, rel %.2g (%zu points)\n", c, got,
                    expected, (got - expected) / expected, p.size());
        EXPECT_NEAR(got / expected, 1.0, 1e-3);
    }
    // The radiance is Ft(η, cos θo)/π · M.
    const glm::vec3 wo = glm::normalize(s.camera.position() - xo);
    const double cosO =
        std::min(1.0, std::fabs(double(glm::dot(glm::vec3(rb.normal[centre]), wo))));
    const double sin2T = (1.0 - cosO * cosO) / (ior * ior);
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (cosO - ior * cosT) / (cosO + ior * cosT);
    const double rp = (ior * cosO - cosT) / (ior * cosO + cosT);
    const double ft = 1.0 - 0.5 * (rs * rs + rp * rp);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(rb.hdr[centre][c] / (ft / M_PI * rb.exitance[centre][c]), 1.0, 1e-5);
}

// A model that does not compile: setModel throws core::Error naming the model file and line,
// and the renderer keeps the previous model (identical image afterwards).
TEST(RenderModel, BrokenModelKeepsPreviousProgram) {
    Fixture& f = fixture();
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    r.render(s);
    const render::Readback before = r.readback();
    const std::string good = testsupport::readText(f.root / "materials/dipole.bssrdf");
    const std::string bad =
        testsupport::replaced(good, "vec3 Dr = sqrt(R + Zr*Zr);", "vec3 Dr = sqrt(R + Zr*Zr;");
    const bssrdf::Model broken = bssrdf::parseModel(bad, "materials/broken.bssrdf");
    try {
        r.setModel(broken);
        FAIL() << "expected a compile error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "materials/broken.bssrdf");
        EXPECT_EQ(e.line(), testsupport::lineOf(bad, "vec3 Dr = sqrt(R + Zr*Zr;")) << e.what();
    }
    EXPECT_TRUE(r.ready());
    r.render(s);
    const render::Readback after = r.readback();
    for (size_t p = 0; p < before.exitance.size(); ++p) {
        EXPECT_EQ(before.exitance[p], after.exitance[p]);
        EXPECT_EQ(before.stats[p], after.stats[p]);
    }
}

// A model returning NaN: the hit pixels' radiance is NaN and the tone-mapped image shows them
// magenta (never black); a valid model's image has no magenta pixel.
TEST(RenderModel, NanFromTheModelShowsMagenta) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    auto magentaOf = [](const render::Readback& rb) {
        size_t n = 0;
        for (size_t p = 0; p < rb.ldr.size() / 4; ++p)
            n += rb.ldr[4 * p] == 255 && rb.ldr[4 * p + 1] == 0 && rb.ldr[4 * p + 2] == 255;
        return n;
    };
    const render::Frame goodFrame = r.render(s);
    const render::Readback good = r.readback();
    EXPECT_EQ(magentaOf(good), 0u);
    EXPECT_FALSE(goodFrame.invalid.any());
    EXPECT_EQ(goodFrame.invalid.surface, hitPixels(good).size());
    const bssrdf::Model nan =
        bssrdf::parseModel("analytic radial no_wi no_wo\n::begin shader\n"
                           "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                           "    return vec3(sqrt(-1.0 - length(Xo - Xi)));\n}\n::end shader\n",
                           "materials/nan.bssrdf");
    r.setModel(nan);
    const render::Frame badFrame = r.render(s);
    const render::Readback bad = r.readback();
    const std::vector<size_t> hits = hitPixels(bad);
    ASSERT_FALSE(hits.empty());
    for (size_t p : hits)
        EXPECT_TRUE(std::isnan(bad.hdr[p].x)) << p;
    EXPECT_EQ(magentaOf(bad), hits.size());
    // and counted (the scene stage's Errors entry)
    EXPECT_EQ(badFrame.invalid.nan, hits.size());
    EXPECT_EQ(badFrame.invalid.surface, hits.size());
    EXPECT_EQ(render::invalidPixelsProblem(badFrame.invalid),
              "L_o is NaN at " + std::to_string(hits.size()) + " of " +
                  std::to_string(hits.size()) +
                  " surface pixels (magenta): the model returned such values");
    // the shared renderer gets its model back for the other tests
    r.setModel(fixture().dipole);
}

// A model with a loop of its own (64 iterations per Bssrdf call) exceeds llvmpipe's 65535 loop
// iterations per invocation at the default dispatch size; the renderer notices (sentinel loop)
// and renders again with fewer iterations per dispatch. The brute-force result then equals the
// slot-order sum of the same BSSRDF values evaluated one per invocation (render_pairs.comp).
TEST(RenderTraversal, ModelLoopsStayWithinTheDriverLimit) {
    Fixture& f = fixture();
    render::Renderer& r = bunnyRenderer();
    const bssrdf::Model loopy = bssrdf::parseModel(
        "analytic\n"
        "::begin parameters\n"
        "float Loops 0 1000 64\n"
        "::end parameters\n"
        "::begin shader\n"
        "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
        "    float r2 = dot(Xo - Xi, Xo - Xi);\n"
        "    vec3 s = vec3(0.0);\n"
        "    for (int i = 0; i < int(Loops); ++i)\n"
        "        s += vec3(1.0, 0.5, 0.25) * exp(-r2 * (0.01 + 0.001 * float(i)));\n"
        "    return s / max(Loops, 1.0);\n"
        "}\n"
        "::end shader\n",
        "materials/loopy.bssrdf");
    r.setModel(loopy);
    r.setMaterial(bssrdf::defaultValues(loopy), skin());
    render::Settings s = smallSettings(bunny().mesh);
    s.width = 32;
    s.height = 24;
    s.bruteForce = true;
    const render::Frame frame = r.render(s);
    std::printf("loopy model: %u iterations per dispatch, %d dispatches\n",
                frame.iterationsPerDispatch, frame.dispatches);
    // llvmpipe (and zink over it) cut an invocation's loops at 65 535 iterations: the model's
    // loop inside the traversal's makes the renderer meet that cut and halve its iterations per
    // dispatch. A GPU driver cuts nothing, so the renderer keeps its full count (NVIDIA:
    // 32 768); the image is right either way.
    const std::string driver = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (driver.find("llvmpipe") != std::string::npos)
        EXPECT_LT(frame.iterationsPerDispatch, render::kIterationsPerDispatch);
    else
        EXPECT_EQ(frame.iterationsPerDispatch, render::kIterationsPerDispatch);
    const render::Readback gpu = r.readback();
    const octree::Octree& tree = bunny().tree;
    const float scale = r.builtins().scale;
    size_t checked = 0;
    for (size_t p : hitPixels(gpu)) {
        if (checked++ % 7 != 0) continue; // a sample of pixels keeps the test fast
        octree::Trace t;
        t.xo = glm::vec3(gpu.position[p]);
        t.no = glm::vec3(gpu.normal[p]);
        for (const auto& q : tree.points) {
            const glm::vec3 e(q.irradiance[0], q.irradiance[1], q.irradiance[2]);
            t.evaluations.push_back(
                {glm::vec3(q.positionArea[0], q.positionArea[1], q.positionArea[2]),
                 glm::vec3(q.normal[0], q.normal[1], q.normal[2]), e * q.positionArea[3]});
        }
        t.steps.resize(1);
        t.steps[0].evaluationCount = uint32_t(t.evaluations.size());
        octree::accumulate(t, r.evaluatePairs(render::tracePairs(t, scale)), scale);
        EXPECT_EQ(gpu.stats[p].z, 0u);
        EXPECT_EQ(gpu.stats[p].w, uint32_t(tree.points.size()));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(gpu.exitance[p][c] / t.radiantExitance[c], 1.0, 1e-5);
    }
    r.setModel(f.dipole);
}

// A G-buffer given from outside (a capture's recorded one) is what the traversal reads: the
// frame equals the one rasterised with that G-buffer's own placement, bit for bit, while the
// renderer still keeps its own rasterisation aside; the offset rasterisation moves the image by
// the offset (the bunny's columns shift by one pixel for an offset of one); the CPU replica
// traversing from the given points sums what the GPU summed; a G-buffer of another size is
// refused naming both sizes.
TEST(RenderGBuffer, AGivenGbufferIsTracedAndTheRasterisedOneKept) {
    render::Renderer& r = bunnyRenderer();
    render::Settings s = smallSettings(bunny().mesh);
    r.setGivenGbuffer(std::nullopt);
    const render::Gbuffer moved = r.rasteriseGbuffer(s, glm::vec2(0.3f, -0.2f));
    s.camera.aspect = float(s.width) / float(s.height);
    r.render(s);
    const render::Readback own = r.readback();
    // one pixel right: the moved image's column x + 1 is the unmoved image's column x
    const render::Gbuffer right = r.rasteriseGbuffer(s, glm::vec2(1.0f, 0.0f));
    size_t compared = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x + 1 < s.width; ++x) {
            const size_t p = own.index(x, y), q = own.index(x + 1, y);
            if (own.position[p].w != 1.0f) continue;
            ++compared;
            EXPECT_EQ(right.position[q].w, 1.0f);
            EXPECT_NEAR(glm::distance(glm::vec3(right.position[q]), glm::vec3(own.position[p])),
                        0.0f, 1e-4f)
                << x << "," << y;
        }
    EXPECT_GT(compared, 300u);

    r.setGivenGbuffer(moved);
    r.render(s);
    const render::Readback traced = r.readback();
    EXPECT_EQ(traced.position, moved.position);
    EXPECT_EQ(traced.normal, moved.normal);
    const render::Gbuffer kept = r.rasterisedGbuffer();
    EXPECT_EQ(kept.position, own.position);
    EXPECT_EQ(kept.normal, own.normal);
    size_t differ = 0;
    for (size_t p = 0; p < own.hdr.size(); ++p)
        differ += traced.exitance[p] != own.exitance[p];
    EXPECT_GT(differ, 100u) << "the moved G-buffer's surface points give other sums";
    // the CPU replica traversing from the given G-buffer's points sums what the GPU summed
    render::Settings direct = s;
    direct.directBssrdf = true; // the replica's values come from Bssrdf() itself
    r.render(direct);
    const render::Readback givenDirect = r.readback();
    EXPECT_EQ(givenDirect.position, moved.position);
    const ReplicaResult replica = compareWithReplica(r, direct, givenDirect, bunny().tree);
    EXPECT_GT(replica.compared, 300u);
    EXPECT_LE(replica.excluded * 50, replica.compared) << "at most 2 % excluded";

    render::Settings bigger = s;
    bigger.width += 1;
    try {
        r.render(bigger);
        ADD_FAILURE() << "a G-buffer of another size was traced";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("the given G-buffer is 64x48, the frame 65x48"),
                  std::string::npos)
            << e.what();
    }
    r.setGivenGbuffer(std::nullopt);
    r.render(s);
    EXPECT_EQ(r.readback().exitance, own.exitance);
}

// The raster rule (render/raster_rule.h): the renderer's own G-buffer, the same drawn with the
// sample points moved by up to 0.2 px (what another driver may do), and drawn with each vertex
// snapped on its own as GL's coarsest grid may, are rasterisations of the mesh by the camera; moved
// by half a pixel, with the normals tilted by 0.02 rad, against a mesh 1 % larger, or with a hole
// punched inside the silhouette, they are not, and the count says which rule failed. One RasterRule
// checks every G-buffer of the mesh (as a replay checks two); an empty mesh or a G-buffer whose
// images do not fit is an error.
TEST(RenderGBuffer, TheRasterRuleAcceptsSubPixelPlacementAndNothingElse) {
    render::Renderer& r = bunnyRenderer();
    const render::Settings s = smallSettings(bunny().mesh);
    const mesh::Mesh& m = bunny().mesh;
    const render::RasterRule rule(m);
    const render::Gbuffer own = r.rasteriseGbuffer(s);
    const render::RasterCheck c = rule.check(own, s.camera);
    std::printf("own G-buffer %dx%d: %zu covered, worst %.3g px off centre, depth %.3g, normal "
                "%.3g\n",
                own.width, own.height, c.covered, c.worstOffCentre, c.worstDepth, c.worstNormal);
    ASSERT_GT(c.covered, 300u);
    EXPECT_EQ(c.failures(), 0u);
    EXPECT_LT(c.worstOffCentre, 0.02) << "llvmpipe samples at the centre";

    std::mt19937 rng(7);
    std::uniform_real_distribution<float> within(-0.2f, 0.2f);
    double worst = 0;
    for (int k = 0; k < 24; ++k) {
        const glm::vec2 off(within(rng), within(rng));
        const render::RasterCheck moved = rule.check(r.rasteriseGbuffer(s, off), s.camera);
        EXPECT_EQ(moved.failures(), 0u)
            << off.x << "," << off.y << ": off centre " << moved.offCentre << ", off surface "
            << moved.offSurface << ", hidden " << moved.hidden << ", normal " << moved.wrongNormal
            << ", uncovered inside " << moved.uncoveredInside;
        EXPECT_NEAR(moved.worstOffCentre, std::max(std::fabs(off.x), std::fabs(off.y)), 0.02);
        worst = std::max(worst, moved.worstNormal);
    }
    std::printf("moved by up to 0.2 px: worst normal difference %.3g\n", worst);

    // each vertex snapped on its own to GL's coarsest grid (up to 1/32 px, half of kSnap) and
    // its depth rounded by 8 ulps, with and without a sample offset: still a rasterisation;
    // each vertex moved by up to a pixel is not (its pixels' points lie on the surface, but off
    // their centres)
    for (const uint32_t seed : {1u, 2u, 3u})
        for (const glm::vec2 off : {glm::vec2(0.0f), glm::vec2(0.15f, -0.1f)}) {
            const gl::VertexSnap snap{float(render::kSnap / 2), 8.0f, seed};
            const render::Gbuffer g = r.rasteriseGbuffer(s, off, snap);
            ASSERT_NE(g.position, r.rasteriseGbuffer(s, off).position) << "nothing snapped";
            const render::RasterCheck snapped = rule.check(g, s.camera);
            EXPECT_EQ(snapped.failures(), 0u)
                << "seed " << seed << ": off centre " << snapped.offCentre << ", off surface "
                << snapped.offSurface << ", hidden " << snapped.hidden << ", normal "
                << snapped.wrongNormal << ", uncovered inside " << snapped.uncoveredInside;
        }
    const render::RasterCheck loose =
        rule.check(r.rasteriseGbuffer(s, {}, gl::VertexSnap{1.0f, 8.0f, 1u}), s.camera);
    EXPECT_GT(loose.offCentre, loose.covered / 2);
    std::printf("each vertex moved by up to 1 px: %zu of %zu covered pixels off centre\n",
                loose.offCentre, loose.covered);

    const render::RasterCheck half =
        rule.check(r.rasteriseGbuffer(s, glm::vec2(0.5f, 0.0f)), s.camera);
    EXPECT_GT(half.offCentre, half.covered * 9 / 10);
    const render::RasterCheck down =
        rule.check(r.rasteriseGbuffer(s, glm::vec2(0.0f, -0.3f)), s.camera);
    EXPECT_GT(down.offCentre, down.covered * 9 / 10);

    render::Gbuffer bent = own; // normals tilted by 0.02 rad about +y
    const glm::mat4 tilt = glm::rotate(glm::mat4(1.0f), 0.02f, glm::vec3(0, 1, 0));
    for (glm::vec4& nv : bent.normal)
        if (nv != glm::vec4(0.0f)) nv = tilt * glm::vec4(glm::vec3(nv), 0.0f);
    const render::RasterCheck b = rule.check(bent, s.camera);
    EXPECT_GT(b.wrongNormal, b.covered * 9 / 10);
    EXPECT_EQ(b.offCentre + b.offSurface, 0u);

    mesh::Mesh larger = m;
    for (auto& v : larger.vertices)
        for (float& x : v)
            x *= 1.01f;
    const render::RasterCheck l = render::checkRasterisation(own, larger, s.camera);
    EXPECT_GT(l.offSurface, l.covered / 2);

    // the surface behind: each covered pixel's point replaced by the next hit along its ray
    render::Gbuffer behind = own;
    mesh::Mesh withNormals = m;
    if (withNormals.normals.size() != withNormals.vertices.size())
        mesh::computeVertexNormals(withNormals);
    const pathtrace::MeshScene scene(withNormals);
    const glm::dvec3 eye(s.camera.position());
    size_t replaced = 0;
    for (glm::vec4& P : behind.position) {
        if (P.w != 1.0f) continue;
        const glm::dvec3 to = glm::dvec3(P) - eye;
        const double dist = glm::length(to);
        const glm::dvec3 d = to / dist;
        const double org[3] = {eye.x, eye.y, eye.z}, dir[3] = {d.x, d.y, d.z};
        double t = 0;
        uint32_t prim = 0;
        if (!scene.intersect(org, dir, dist * 1.01, 1e9, t, prim)) continue;
        P = glm::vec4(glm::vec3(eye + t * d), 1.0f);
        ++replaced;
    }
    ASSERT_GT(replaced, 100u);
    const render::RasterCheck hid = rule.check(behind, s.camera);
    EXPECT_GT(hid.hidden, replaced * 9 / 10);
    EXPECT_EQ(hid.offSurface, 0u);

    render::Gbuffer holed = own;
    size_t inner = 0;
    for (int y = 1; y + 1 < own.height && !inner; ++y)
        for (int x = 1; x + 1 < own.width && !inner; ++x) {
            bool all = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    all = all && own.position[size_t((y + dy) * own.width + x + dx)].w == 1.0f;
            if (all) inner = size_t(y * own.width + x);
        }
    ASSERT_NE(inner, 0u);
    holed.position[inner] = holed.normal[inner] = glm::vec4(0.0f);
    const render::RasterCheck h = rule.check(holed, s.camera);
    EXPECT_EQ(h.uncoveredInside, 1u);
    EXPECT_EQ(h.failures(), 1u);

    // bad inputs: a mesh without triangles, a G-buffer whose images do not fit its size
    auto expectError = [](const std::function<void()>& f, const std::string& fragment) {
        try {
            f();
            ADD_FAILURE() << "no error; expected: " << fragment;
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    expectError([] { const render::RasterRule none{mesh::Mesh{}}; },
                "the mesh to check against has no triangles");
    render::Gbuffer cut = own;
    cut.normal.pop_back();
    expectError([&] { rule.check(cut, s.camera); }, "its images do not fit");
    expectError([&] { rule.check(render::Gbuffer{}, s.camera); }, "the G-buffer to check is empty");
}
