// The scene's second renderer: brute force and the A/B view's B side (scene_comparison.h).
#include "pipeline/scene_comparison.h"

#include "core/core.h"

namespace app {

SceneComparison::SceneComparison(std::filesystem::path root, const std::optional<mesh::Mesh>& mesh,
                                 const std::optional<octree::Octree>& tree, uint32_t iterations)
    : m_root(std::move(root)), m_mesh(mesh), m_tree(tree), m_iterations(iterations) {}

void SceneComparison::setFrameModel(const bssrdf::Model& model, const bssrdf::ParamValues& values,
                                    const bssrdf::Builtins& builtins) {
    m_frameModel = model;
    m_frameValues = values;
    m_frameBuiltins = builtins;
}

void SceneComparison::frameShown(int width, int height) {
    m_shownWidth = width;
    m_shownHeight = height;
    ++m_shown;
}

void SceneComparison::request(const Request& r) {
    if (m_shownWidth <= 0 || !m_tree || !m_mesh || !m_frameModel)
        throw core::Error("render", 0, "no rendered frame to compare with yet");
    // A second renderer with its own buffers, so the displayed frame stays as it is.
    if (!m_renderer) m_renderer = std::make_unique<render::Renderer>(shader::Sources{m_root});
    m_renderer->setMesh(*m_mesh);
    m_renderer->setOctree(*m_tree);
    m_isBrute = r.model == nullptr;
    m_name = m_isBrute ? "brute force" : r.name;
    m_renderer->setModel(m_isBrute ? *m_frameModel : *r.model);
    m_renderer->setMaterial(m_isBrute ? m_frameValues : r.values,
                            m_isBrute ? m_frameBuiltins : r.builtins);
    render::Settings bs = m_frameSettings;
    bs.width = m_shownWidth;
    bs.height = m_shownHeight;
    bs.bruteForce = m_isBrute || m_frameSettings.bruteForce;
    bs.iterationsPerDispatch = m_iterations;
    m_renderer->begin(bs);
    m_for = m_shown;
    m_doneFor = -1; // the previous comparison no longer stands
    m_running = true;
}

bool SceneComparison::advance(double budgetMs) {
    if (!m_running) return false;
    try {
        if (!m_renderer->advance(budgetMs)) return false;
        render::Readback rb = m_renderer->readback();
        m_exitance = std::move(rb.exitance);
        m_image = std::move(rb.ldr);
        m_doneFor = m_for;
    } catch (const std::exception& ex) {
        m_problem = ex.what();
        core::logError("brute force: " + m_problem);
    }
    m_running = false;
    return true;
}

const std::vector<glm::vec4>* SceneComparison::bruteForceResult() const {
    return m_isBrute && m_doneFor == m_shown && !m_exitance.empty() ? &m_exitance : nullptr;
}

const std::vector<unsigned char>* SceneComparison::image() const {
    return m_doneFor == m_shown && !m_image.empty() ? &m_image : nullptr;
}

shader::Reloaded SceneComparison::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    return m_renderer ? m_renderer->reloadShaders(changed) : shader::Reloaded{};
}

shader::Records SceneComparison::shaderRecords() const {
    return m_renderer ? m_renderer->shaderRecords() : shader::Records{};
}

} // namespace app
