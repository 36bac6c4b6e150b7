// Captures of the mesh pipeline (thesis 3.3; format v1, captures/README.md): SceneStage's
// entries —
//   scene.mesh         csv, exact   vertices, triangles, area, hash of the prepared mesh
//   scene.pointcloud   csv, exact   count, nearest-neighbour metrics, content hash
//   scene.octree       csv, exact   node/leaf counts, depth, bytes, hash, nodes per depth
//   scene.irradiance_unshadowed  csv, tol   per-point E_u, E_t = E_u · V (GPU; directional and
//                                           filtered light)
//   scene.visibility   csv, tol     per-point shadow-map visibility V (GPU; the same lights; a
//                                   replay allows each V what a shadow map drawn 1/16 texel
//                                   aside moves it: another rasteriser's sub-pixel precision)
//   scene.irradiance   csv, tol     per-point E_t (GPU): recorded for the other lights (occluded
//                                   IBL: a replay allows each value 2^-7 of its unshadowed sum);
//                                   made for the replay of captures from before the split otherwise
//   scene.gbuffer_position, scene.gbuffer_normal  exr_input
//                                   the G-buffer the traversal read (GPU): surface point and
//                                   normal per pixel (a miss: 0, 0, 0 in both); a replay gives
//                                   the recorded one to the traversal (hash checked)
//   scene.gbuffer_rule csv, exact   pixels breaking the raster rule (render/raster_rule.h) in
//                                   the traced G-buffer and in this run's rasterisation
//   scene.render       exr, tol     the rendered HDR radiance (GPU)
//   scene.trace_steps  csv, exact   one pixel's traversal steps (CPU replica): node, decision,
//                                   depth, stack after each step
//   scene.trace_values csv, tol     that trace's contributions and running sums
// and the mesh file as an input. On replay the octree and the render read the recorded
// irradiance (E_u · V, else E_t; recordedIrradiance), as they read the recorded G-buffer, while
// the irradiance entries compare this run's own. Hashes are split into four 16-bit integers so that
// they compare exactly as numbers. The texture-space stages' entries: texspace_stage.cpp.
#include "pipeline/scene_stage.h"

#include "core/core.h"
#include "core/text.h"
#include "pointcloud/pointcloud.h"
#include "render/raster_rule.h"

#include <algorithm>
#include <cmath>

namespace app {

namespace {

// Float tolerances (stated in the manifest):
// per-point irradiance: Ft, cos and the PCF average in float32, a handful of roundings of
// 2^-24 each; 1e-5 relative, plus 1e-7 absolute for values that are ~0 in shadow. That holds
// for E_u; the visibility V of a filtered shadow lookup moves by up to
// irradiance::kVisibilityTolerance (absolute) between samplers that round the bilinear weights
// differently, so with a shadow map E_t is recorded as those two factors.
constexpr double kIrradianceRel = 1e-5, kIrradianceAbs = 1e-7;
// render: a float32 sum of up to ~10^4 contributions (each Bssrdf() within a few ulp: GLSL
// exp is (3 + 2|x|) ulp) — worst case n·2^-24 ≈ 6e-4 relative for the longest sums, typically
// √n·2^-24; 1e-4 relative plus an absolute floor of 1e-6 of the image maximum.
constexpr double kRenderRel = 1e-4;
constexpr double kTraceRel = 1e-4;
constexpr const char* kGbufferStages[2] = {"scene.gbuffer_position", "scene.gbuffer_normal"};

} // namespace

// The recorded G-buffer of a capture, when it has both images (a miss: a zero normal; a hit's
// normal is never zero, render_gbuffer.frag).
std::optional<render::Gbuffer> SceneStage::recordedGbuffer(const CaptureEntries& out) {
    if (!out.recordedImage) return std::nullopt;
    const std::optional<pathtrace::Image> pos = out.recordedImage(kGbufferStages[0]);
    const std::optional<pathtrace::Image> nrm = out.recordedImage(kGbufferStages[1]);
    if (!pos || !nrm) return std::nullopt;
    if (pos->width != nrm->width || pos->height != nrm->height)
        throw core::Error("scene", 0,
                          "the recorded G-buffer's position and normal images differ in size");
    render::Gbuffer g;
    g.width = pos->width;
    g.height = pos->height;
    const size_t n = size_t(g.width) * size_t(g.height);
    g.position.resize(n);
    g.normal.resize(n);
    for (size_t p = 0; p < n; ++p) {
        const glm::vec3 x(pos->mean[3 * p], pos->mean[3 * p + 1], pos->mean[3 * p + 2]);
        const glm::vec3 nv(nrm->mean[3 * p], nrm->mean[3 * p + 1], nrm->mean[3 * p + 2]);
        const bool hit = nv != glm::vec3(0.0f);
        g.position[p] = glm::vec4(x, hit ? 1.0f : 0.0f);
        g.normal[p] = glm::vec4(nv, 0.0f);
    }
    return g;
}

namespace {

// The transmitted irradiance the traversal read when the capture was made, where it has it:
// E_u · V of the recorded factors in float (as irradiance_direct.comp forms E_t, so on the
// recording driver bit for bit), else the recorded E_t; `from` names the tables.
std::optional<std::vector<glm::vec3>> recordedIrradiance(const CaptureEntries& out,
                                                         std::string& from) {
    if (!out.recordedTable) return std::nullopt;
    const auto rows = [](const capture::Table& t, size_t columns, const char* stage) {
        for (size_t i = 0; i < t.rows.size(); ++i)
            if (t.columns.size() != columns || t.rows[i][0] != double(i))
                throw core::Error(std::string(stage), 0,
                                  "the recorded table is not one row per point in order (row " +
                                      std::to_string(i + 1) + ")");
        return t.rows.size();
    };
    const std::optional<capture::Table> eu = out.recordedTable("scene.irradiance_unshadowed");
    const std::optional<capture::Table> v = out.recordedTable("scene.visibility");
    std::vector<glm::vec3> e;
    if (eu && v) {
        const size_t n = rows(*eu, 4, "scene.irradiance_unshadowed");
        if (rows(*v, 2, "scene.visibility") != n)
            throw core::Error("scene.visibility", 0,
                              "the recorded table has " + std::to_string(v->rows.size()) +
                                  " points, scene.irradiance_unshadowed " + std::to_string(n));
        for (size_t i = 0; i < n; ++i) {
            const std::vector<double>& r = eu->rows[i];
            e.push_back(glm::vec3(float(r[1]), float(r[2]), float(r[3])) * float(v->rows[i][1]));
        }
        from = "scene.irradiance_unshadowed x scene.visibility";
        return e;
    }
    const std::optional<capture::Table> et = out.recordedTable("scene.irradiance");
    if (!et) return std::nullopt;
    for (size_t i = 0, n = rows(*et, 4, "scene.irradiance"); i < n; ++i)
        e.emplace_back(float(et->rows[i][1]), float(et->rows[i][2]), float(et->rows[i][3]));
    from = "scene.irradiance";
    return e;
}

// One image of the G-buffer the traversal read, recorded as the replay's input.
CaptureEntry gbufferEntry(int which, const render::Readback& rb) {
    CaptureEntry e = captureEntry(CaptureEntry::Kind::ExrInput, kGbufferStages[which]);
    const std::vector<glm::vec4>& v = which == 0 ? rb.position : rb.normal;
    e.image.width = rb.width;
    e.image.height = rb.height;
    e.image.samples = 1;
    for (const glm::vec4& x : v)
        for (int c = 0; c < 3; ++c)
            e.image.mean.push_back(x[c]);
    e.image.variance.assign(e.image.mean.size(), 0.0f);
    e.note = std::string("the G-buffer's ") + (which == 0 ? "surface points" : "normals") +
             " the traversal read (a miss: 0), given to it again on replay; checked against the "
             "mesh and camera in scene.gbuffer_rule";
    return e;
}

// The raster rule's counts (render/raster_rule.h) as a table row.
std::vector<double> ruleRow(int which, const render::RasterCheck& c) {
    return {double(which),    double(c.pixels),      double(c.offCentre),      double(c.offSurface),
            double(c.hidden), double(c.wrongNormal), double(c.uncoveredInside)};
}
std::string ruleComment(const char* what, const render::RasterCheck& c) {
    return std::string(what) + ": " + std::to_string(c.covered) + " covered pixels, worst " +
           core::formatNumber(c.worstOffCentre, 3) + " px off centre, " +
           core::formatNumber(c.worstDepth, 3) + " off the plane (relative), normal " +
           core::formatNumber(c.worstNormal, 3);
}

// Appends a content hash as four 16-bit integers.
void pushHash(std::vector<double>& row, const std::string& hash) {
    const std::string hex = hash.substr(hash.find(':') + 1);
    for (int k = 0; k < 4; ++k)
        row.push_back(double(std::stoul(hex.substr(size_t(4 * k), 4), nullptr, 16)));
}

} // namespace

void SceneStage::capture(const SceneModelInput& model, CaptureEntries& out) {
    if (!m_settings.enabled) return;
    { // the mesh is an input: path and content hash
        const std::filesystem::path meshPath =
            std::filesystem::path(m_settings.meshFile).is_absolute()
                ? std::filesystem::path(m_settings.meshFile)
                : m_root / m_settings.meshFile;
        const std::string text = core::readFile(meshPath);
        out.inputs.push_back({m_settings.meshFile, core::hashHex(text),
                              "(mesh, " + std::to_string(text.size()) + " bytes)"});
    }
    // On replay the traversal reads the recorded G-buffer (its size checked against the
    // settings' frame); the renderer goes back to its own rasterisation afterwards.
    const std::optional<render::Gbuffer> given = recordedGbuffer(out);
    if (given &&
        (given->width != m_settings.render.width || given->height != m_settings.render.height))
        throw core::Error(std::string(kGbufferStages[0]) + ": the recorded G-buffer is " +
                          std::to_string(given->width) + "x" + std::to_string(given->height) +
                          ", settings.scene.render renders " +
                          std::to_string(m_settings.render.width) + "x" +
                          std::to_string(m_settings.render.height));
    // The traversal reads the recorded irradiance too (kept apart from this run's own, which
    // the irradiance entries compare): E_t's visibility is a sampler's choice within 2^-7.
    std::string irradianceFrom;
    std::optional<std::vector<glm::vec3>> givenIrradiance = recordedIrradiance(out, irradianceFrom);
    struct Restore {
        SceneStage& s;
        bool gbuffer, irradiance;
        ~Restore() {
            if (gbuffer) s.setGivenGbuffer(std::nullopt);
            if (irradiance) s.setGivenIrradiance(std::nullopt);
        }
    } restore{*this, given.has_value(), givenIrradiance.has_value()};
    if (given) setGivenGbuffer(given);
    if (givenIrradiance) {
        out.notes.push_back("scene: the octree and the render read the recorded irradiance (" +
                            irradianceFrom + "); this run's own is compared with it");
        setGivenIrradiance(std::move(givenIrradiance));
    }
    finish(model);
    for (const auto& p : problems())
        throw core::Error(p);
    if (!hasFrame() || !tree()) throw core::Error("scene", 0, "nothing was rendered");
    const int traceX = out.traceX, traceY = out.traceY;

    const mesh::Mesh& m = mesh();
    CaptureEntry mt = captureEntry(CaptureEntry::Kind::Csv, "scene.mesh");
    mt.note = "CPU (OBJ parse + normalisation): exact";
    mt.table.comments = {"mesh " + m_settings.meshFile + " after preparation",
                         "hash " + meshHash()};
    mt.table.columns = {"vertices", "triangles", "area", "h0", "h1", "h2", "h3"};
    std::vector<double> row{double(m.vertices.size()), double(m.triangles.size()),
                            pointcloud::meshArea(m)};
    pushHash(row, meshHash());
    mt.table.rows.push_back(row);
    out.entries.push_back(std::move(mt));

    const pointcloud::PointCloud& pc = m_cloud;
    std::string bytes(reinterpret_cast<const char*>(pc.points.data()),
                      pc.points.size() * sizeof(pc.points[0]));
    const std::string cloudHash = core::hashHex(bytes);
    const auto& u = uniformity();
    CaptureEntry pt = captureEntry(CaptureEntry::Kind::Csv, "scene.pointcloud");
    pt.note = "CPU, deterministic for any thread count: exact";
    pt.table.comments = {"hash " + cloudHash};
    pt.table.columns = {"count",  "area", "mean_nn", "cv_nn", "min_nn",
                        "max_nn", "h0",   "h1",      "h2",    "h3"};
    row = {double(pc.points.size()), pc.totalArea, u.meanNN, u.cvNN, u.minNN, u.maxNN};
    pushHash(row, cloudHash);
    pt.table.rows.push_back(row);
    out.entries.push_back(std::move(pt));

    const octree::Octree& t = *tree();
    // The tree's hash covers the node records, which hold irradiance sums (GPU): hash the
    // CPU-built structure only (descriptors and point order).
    std::string tb(reinterpret_cast<const char*>(t.descriptors.data()),
                   t.descriptors.size() * sizeof(uint32_t));
    tb.append(reinterpret_cast<const char*>(t.order.data()), t.order.size() * sizeof(uint32_t));
    const std::string treeHash = core::hashHex(tb);
    CaptureEntry ot = captureEntry(CaptureEntry::Kind::Csv, "scene.octree", "depth");
    ot.note = "CPU build: exact (structure hash: descriptors + point order)";
    ot.table.comments = {"hash " + treeHash,
                         "first row: depth -1 = totals (nodes, leaves, max depth, bytes)"};
    ot.table.columns = {"depth", "nodes", "leaves_or_maxdepth", "bytes", "h0", "h1", "h2", "h3"};
    row = {-1, double(t.stats.nodes), double(t.stats.leaves), double(t.stats.bytes)};
    pushHash(row, treeHash);
    ot.table.rows.push_back(row);
    for (size_t d = 0; d < t.stats.nodesPerDepth.size(); ++d)
        ot.table.rows.push_back({double(d), double(t.stats.nodesPerDepth[d]), 0, 0, 0, 0, 0, 0});
    out.entries.push_back(std::move(ot));

    const auto& e = irradiance();
    const bool factored = irradiance::hasVisibilityFactor(m_settings.light.mode);
    CaptureEntry it = captureEntry(CaptureEntry::Kind::Csv, "scene.irradiance", "point");
    it.absTol = kIrradianceAbs;
    it.relTol = kIrradianceRel;
    it.note = "GPU float32 Ft*cos*visibility per point: 1e-5 relative + 1e-7";
    it.table.comments = {"transmitted irradiance E_t per point (input order)"};
    it.table.columns = {"point", "R", "G", "B"};
    for (size_t i = 0; i < e.size(); ++i)
        it.table.rows.push_back({double(i), e[i].x, e[i].y, e[i].z});
    it.recorded = !factored;
    if (m_settings.light.mode == irradiance::LightMode::OccludedIbl && out.forReplay) {
        irradiance::Settings light = m_settings.light;
        light.ior = lightIor(model);
        std::vector<glm::vec3> normals(m_cloud.points.size());
        for (size_t i = 0; i < normals.size(); ++i)
            normals[i] =
                glm::vec3(m_cloud.points[i].n[0], m_cloud.points[i].n[1], m_cloud.points[i].n[2]);
        addOcclusionAllowance(it, m_irradiance_stage->occludedUnshadowed(light, normals),
                              m_irradiance_stage->occludedRasterSpread(light));
    }
    out.entries.push_back(std::move(it));
    if (factored) {
        irradiance::Settings light = m_settings.light;
        light.ior = lightIor(model);
        const irradiance::Stage::Factors f = m_irradiance_stage->factors(light);
        CaptureEntry eu =
            captureEntry(CaptureEntry::Kind::Csv, "scene.irradiance_unshadowed", "point");
        // filtered light: plus what T(uv)'s bilinear weights may move on another driver
        const double spread = m_irradiance_stage->unshadowedSpread(light);
        eu.absTol = kIrradianceAbs + spread;
        eu.relTol = kIrradianceRel;
        eu.note = "GPU float32 Ft*cos per point (E_t = this times the visibility): 1e-5 "
                  "relative + 1e-7" +
                  projectedSpreadNote(spread);
        eu.table.comments = {"unshadowed transmitted irradiance E_u per point (input order)"};
        eu.table.columns = {"point", "R", "G", "B"};
        for (size_t i = 0; i < f.unshadowed.size(); ++i)
            eu.table.rows.push_back(
                {double(i), f.unshadowed[i].x, f.unshadowed[i].y, f.unshadowed[i].z});
        out.entries.push_back(std::move(eu));
        CaptureEntry v = visibilityEntry("scene.visibility", "point");
        v.table.comments = {"visibility V per point (input order)"};
        for (size_t i = 0; i < f.visibility.size(); ++i)
            v.table.rows.push_back({double(i), f.visibility[i]});
        if (out.forReplay) addRasterAllowance(v, m_irradiance_stage->visibilitySpread(light));
        out.entries.push_back(std::move(v));
    }

    const render::Readback rb = readback();
    // The G-buffer: recorded as the traversal read it (on replay the recorded one), and that
    // and this run's own rasterisation checked against the mesh and camera by the raster rule:
    // independent of where another driver places its samples, so the counts compare exactly.
    for (int which = 0; which < 2; ++which)
        out.entries.push_back(gbufferEntry(which, rb));
    {
        const render::Gbuffer traced{rb.width, rb.height, rb.position, rb.normal};
        const render::RasterRule rasterRule(m);
        const render::RasterCheck a = rasterRule.check(traced, m_settings.render.camera);
        const render::RasterCheck b =
            m_renderer->hasGivenGbuffer()
                ? rasterRule.check(m_renderer->rasterisedGbuffer(), m_settings.render.camera)
                : a;
        CaptureEntry rule = captureEntry(CaptureEntry::Kind::Csv, "scene.gbuffer_rule", "gbuffer");
        rule.note = "raster rule (render/raster_rule.h): pixels breaking it, counted against the "
                    "mesh and camera by a CPU ray caster: exact";
        rule.table.comments = {"gbuffer 0: the one traced (the recorded one on replay), 1: this "
                               "run's rasterisation",
                               ruleComment("traced", a), ruleComment("rasterised", b)};
        rule.table.columns = {"gbuffer", "pixels",       "off_centre",      "off_surface",
                              "hidden",  "wrong_normal", "uncovered_inside"};
        rule.table.rows = {ruleRow(0, a), ruleRow(1, b)};
        out.entries.push_back(std::move(rule));
    }

    CaptureEntry img = captureEntry(CaptureEntry::Kind::Exr, "scene.render");
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
    out.entries.push_back(std::move(img));

    if (traceX >= 0 && traceY >= 0) {
        PixelDebug d = debugPixel(traceX, traceY);
        CaptureEntry ts = captureEntry(CaptureEntry::Kind::Csv, "scene.trace_steps", "step");
        ts.note = "CPU replica of Algorithm 2: exact";
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
        out.entries.push_back(std::move(ts));
        CaptureEntry tv = captureEntry(CaptureEntry::Kind::Csv, "scene.trace_values", "step");
        tv.relTol = kTraceRel;
        tv.note = "GPU-evaluated Bssrdf() summed in float: 1e-4 relative";
        tv.table.columns = {"step", "R", "G", "B", "sum_R", "sum_G", "sum_B"};
        for (size_t k = 0; k < d.trace.steps.size(); ++k) {
            const octree::Step& s = d.trace.steps[k];
            tv.table.rows.push_back({double(k), s.contribution.x, s.contribution.y,
                                     s.contribution.z, s.runningSum.x, s.runningSum.y,
                                     s.runningSum.z});
        }
        if (tv.table.rows.empty()) tv.table.rows.push_back({-1, 0, 0, 0, 0, 0, 0});
        out.entries.push_back(std::move(tv));
    }
}

} // namespace app
