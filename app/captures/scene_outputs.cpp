// Captures of the mesh pipeline (capture_scene.h).
#include "captures/scene_outputs.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>

namespace app {
using nlohmann::json;

namespace {

// Float tolerances (stated in the manifest):
// per-point irradiance: Ft, cos and the PCF average in float32, a handful of roundings of
// 2^-24 each; 1e-5 relative, plus 1e-7 absolute for values that are ~0 in shadow.
constexpr double kIrradianceRel = 1e-5, kIrradianceAbs = 1e-7;
// render: a float32 sum of up to ~10^4 contributions (each Bssrdf() within a few ulp: GLSL
// exp is (3 + 2|x|) ulp) — worst case n·2^-24 ≈ 6e-4 relative for the longest sums, typically
// √n·2^-24; 1e-4 relative plus an absolute floor of 1e-6 of the image maximum.
constexpr double kRenderRel = 1e-4;
constexpr double kTraceRel = 1e-4;
// E′ = E_t · A_S/A_T: the irradiance's float32 roundings and one more product.
constexpr double kEprimeRel = 2e-5, kEprimeAbs = 1e-7;

void pushHash(std::vector<double>& row, const std::string& hash) {
    const std::string hex = hash.substr(hash.find(':') + 1);
    for (int k = 0; k < 4; ++k)
        row.push_back(double(std::stoul(hex.substr(size_t(4 * k), 4), nullptr, 16)));
}

// The texture-space stages (seed 004) of the scene's mesh and light.
void textureSpaceTables(Workbench& wb, SceneCapture& out) {
    wb.finishTextureSpace();
    const texspace::Pipeline& p = *wb.textureSpace().pipeline();
    const texspace::Texels& t = p.texels();
    const texspace::Parameterization& param = p.parameterization();
    SceneCaptureTable tx{"texture_space.texels",
                         "texture_space_texels.csv",
                         "",
                         {},
                         0,
                         0,
                         "CPU (parameterisation and rasterisation in double): exact"};
    tx.table.comments = {"texture side K, atlas layout side, 1 = the mesh's UVs, covered texels, "
                         "triangles with a texel, largest stretch sigma1/sigma2"};
    tx.table.columns = {"K", "layout", "from_mesh", "covered", "triangles", "max_stretch"};
    std::vector<char> hasTexel(param.uv.size(), 0);
    for (int32_t f : t.triangle)
        if (f >= 0) hasTexel[size_t(f)] = 1;
    double worst = 1;
    for (double x : param.stretch)
        worst = std::max(worst, x);
    tx.table.rows.push_back({double(t.size), double(p.layoutSize()), param.fromMesh ? 1.0 : 0.0,
                             double(t.covered),
                             double(std::count(hasTexel.begin(), hasTexel.end(), 1)), worst});
    out.tables.push_back(std::move(tx));

    SceneCaptureTable ep{"texture_space.eprime",
                         "texture_space_eprime.csv",
                         "texel",
                         {},
                         kEprimeAbs,
                         kEprimeRel,
                         "GPU irradiance (float32) times the area ratio: 2e-5 relative + 1e-7"};
    ep.table.columns = {"texel", "R", "G", "B"};
    const std::vector<glm::vec3> e = p.eprime();
    size_t k = 0;
    for (size_t texel = 0; texel < e.size(); ++texel)
        if (t.triangle[texel] >= 0 && k++ % 8 == 0)
            ep.table.rows.push_back({double(texel), e[texel].x, e[texel].y, e[texel].z});
    out.tables.push_back(std::move(ep));

    SceneCaptureTable sm{"texture_space.samples",
                         "texture_space_samples.csv",
                         "draw",
                         {},
                         0,
                         0,
                         "the GPU descent of Algorithm 3.1 over the float CDF: exact on one "
                         "driver (a float/double boundary may move a draw on another)"};
    sm.table.columns = {"draw", "texel"};
    const texspace::SampleSet first =
        p.drawSet(std::min(256, wb.textureSpaceSettings().sampling.samples),
                  wb.textureSpaceSettings().sampling.seed, 0);
    for (size_t d = 0; d < first.draws.size(); ++d)
        sm.table.rows.push_back({double(d), double(first.draws[d])});
    if (sm.table.rows.empty()) sm.table.rows.push_back({-1, 0}); // no light: no draws
    out.tables.push_back(std::move(sm));
}

} // namespace

capture::Table renderTable(const pathtrace::Image& img) {
    capture::Table t;
    t.columns = {"x", "y", "R", "G", "B"};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const size_t p = size_t(y) * size_t(img.width) + size_t(x);
            t.rows.push_back(
                {double(x), double(y), img.mean[3 * p], img.mean[3 * p + 1], img.mean[3 * p + 2]});
        }
    return t;
}

SceneCapture sceneOutputs(Workbench& wb, int traceX, int traceY) {
    SceneCapture out;
    SceneStage& scene = wb.scene();
    if (!scene.settings().enabled) return out;
    wb.finishScene();
    for (const auto& p : scene.problems())
        throw core::Error(p);
    if (!scene.hasFrame() || !scene.tree()) throw core::Error("scene", 0, "nothing was rendered");

    const mesh::Mesh& m = scene.mesh();
    SceneCaptureTable mt{
        "scene.mesh", "scene_mesh.csv", "", {}, 0, 0, "CPU (OBJ parse + normalisation): exact"};
    mt.table.comments = {"mesh " + scene.settings().meshFile + " after preparation",
                         "hash " + scene.meshHash()};
    mt.table.columns = {"vertices", "triangles", "area", "h0", "h1", "h2", "h3"};
    std::vector<double> row{double(m.vertices.size()), double(m.triangles.size()),
                            pointcloud::meshArea(m)};
    pushHash(row, scene.meshHash());
    mt.table.rows.push_back(row);
    out.tables.push_back(std::move(mt));

    const auto& cloud = scene.cloud();
    std::string bytes(reinterpret_cast<const char*>(cloud.points.data()),
                      cloud.points.size() * sizeof(cloud.points[0]));
    const std::string cloudHash = core::hashHex(bytes);
    const auto& u = scene.uniformity();
    SceneCaptureTable pt{"scene.pointcloud",
                         "scene_pointcloud.csv",
                         "",
                         {},
                         0,
                         0,
                         "CPU, deterministic for any thread count: exact"};
    pt.table.comments = {"hash " + cloudHash};
    pt.table.columns = {"count",  "area", "mean_nn", "cv_nn", "min_nn",
                        "max_nn", "h0",   "h1",      "h2",    "h3"};
    row = {double(cloud.points.size()), cloud.totalArea, u.meanNN, u.cvNN, u.minNN, u.maxNN};
    pushHash(row, cloudHash);
    pt.table.rows.push_back(row);
    out.tables.push_back(std::move(pt));

    const octree::Octree& t = *scene.tree();
    // The tree's hash covers the node records, which hold irradiance sums (GPU): hash the
    // CPU-built structure only (descriptors and point order).
    std::string tb(reinterpret_cast<const char*>(t.descriptors.data()),
                   t.descriptors.size() * sizeof(uint32_t));
    tb.append(reinterpret_cast<const char*>(t.order.data()), t.order.size() * sizeof(uint32_t));
    const std::string treeHash = core::hashHex(tb);
    SceneCaptureTable ot{"scene.octree",
                         "scene_octree.csv",
                         "depth",
                         {},
                         0,
                         0,
                         "CPU build: exact (structure hash: descriptors + point order)"};
    ot.table.comments = {"hash " + treeHash,
                         "first row: depth -1 = totals (nodes, leaves, max depth, bytes)"};
    ot.table.columns = {"depth", "nodes", "leaves_or_maxdepth", "bytes", "h0", "h1", "h2", "h3"};
    row = {-1, double(t.stats.nodes), double(t.stats.leaves), double(t.stats.bytes)};
    pushHash(row, treeHash);
    ot.table.rows.push_back(row);
    for (size_t d = 0; d < t.stats.nodesPerDepth.size(); ++d)
        ot.table.rows.push_back({double(d), double(t.stats.nodesPerDepth[d]), 0, 0, 0, 0, 0, 0});
    out.tables.push_back(std::move(ot));

    SceneCaptureTable it{"scene.irradiance",
                         "scene_irradiance.csv",
                         "point",
                         {},
                         kIrradianceAbs,
                         kIrradianceRel,
                         "GPU float32 Ft*cos*visibility per point: 1e-5 relative + 1e-7"};
    it.table.comments = {"transmitted irradiance E_t per point (input order)"};
    it.table.columns = {"point", "R", "G", "B"};
    const auto& e = scene.irradiance();
    for (size_t i = 0; i < e.size(); ++i)
        it.table.rows.push_back({double(i), e[i].x, e[i].y, e[i].z});
    out.tables.push_back(std::move(it));

    const render::Readback rb = scene.readback();
    SceneCaptureImage img;
    img.stage = "scene.render";
    img.file = "scene_render.exr";
    img.image.width = rb.width;
    img.image.height = rb.height;
    img.image.samples = 1;
    double maxV = 0;
    for (size_t p = 0; p < rb.hdr.size(); ++p)
        for (int c = 0; c < 3; ++c) {
            img.image.mean.push_back(rb.hdr[p][c]);
            maxV = std::max(maxV, double(rb.hdr[p][c]));
        }
    img.image.variance.assign(img.image.mean.size(), 0.0f);
    img.relTol = kRenderRel;
    img.absTol = 1e-6 * maxV;
    img.note = "GPU float32 sums of up to ~1e4 Bssrdf() terms: 1e-4 relative + 1e-6 of the max";
    out.image = std::move(img);

    if (traceX >= 0 && traceY >= 0) {
        PixelDebug d = scene.debugPixel(traceX, traceY);
        SceneCaptureTable ts{"scene.trace_steps",
                             "scene_trace_steps.csv",
                             "step",
                             {},
                             0,
                             0,
                             "CPU replica of Algorithm 2: exact"};
        ts.table.comments = {
            "pixel " + std::to_string(traceX) + "," + std::to_string(traceY) +
                (d.hit ? "" : " (background)"),
            "decision 0 recurse, 1 node, 2 points; stack entries node<<8|childnum"};
        ts.table.columns = {"step",        "node",       "decision",  "depth",
                            "solid_angle", "stack_size", "stack_top", "evaluations"};
        for (size_t k = 0; k < d.trace.steps.size(); ++k) {
            const octree::Step& s = d.trace.steps[k];
            ts.table.rows.push_back({double(k), double(s.node), double(int(s.decision)),
                                     double(s.depth), double(s.solidAngle), double(s.stack.size()),
                                     s.stack.empty() ? -1.0 : double(s.stack.back()),
                                     double(s.evaluationCount)});
        }
        if (ts.table.rows.empty()) ts.table.rows.push_back({-1, 0, 0, 0, 0, 0, 0, 0});
        out.tables.push_back(std::move(ts));
        SceneCaptureTable tv{"scene.trace_values",
                             "scene_trace_values.csv",
                             "step",
                             {},
                             0,
                             kTraceRel,
                             "GPU-evaluated Bssrdf() summed in float: 1e-4 relative"};
        tv.table.columns = {"step", "R", "G", "B", "sum_R", "sum_G", "sum_B"};
        for (size_t k = 0; k < d.trace.steps.size(); ++k) {
            const octree::Step& s = d.trace.steps[k];
            tv.table.rows.push_back({double(k), s.contribution.x, s.contribution.y,
                                     s.contribution.z, s.runningSum.x, s.runningSum.y,
                                     s.runningSum.z});
        }
        if (tv.table.rows.empty()) tv.table.rows.push_back({-1, 0, 0, 0, 0, 0, 0});
        out.tables.push_back(std::move(tv));
    }
    if (wb.textureSpaceSettings().enabled) textureSpaceTables(wb, out);
    return out;
}

} // namespace app
