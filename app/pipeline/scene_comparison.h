// The scene's second renderer (SceneStage::comparison()), with its own buffers so the displayed
// frame stays as it is. Two uses:
//   - the full-frame brute force of the last frame's view (same size and settings) for the
//     relative-error heatmap;
//   - the B side of the Render panel's A/B view: brute force of the shown frame's model, or
//     another model rendered hierarchically with its own parameters and material, same view,
//     size and settings.
// Progressive: a request starts a pass, SceneStage::update() advances it within the frame budget;
// the result (M per pixel, rgb, and hit in a; the tone-mapped image) belongs to the frame it was
// started for and is returned only while that frame is the shown one.
#pragma once

#include "render/render.h"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app {

class SceneComparison {
  public:
    // The scene a pass renders: SceneStage's mesh and octree as they are when it is requested;
    // passes are sliced into dispatches of `iterations` traversal loop iterations per pixel.
    SceneComparison(std::filesystem::path root, const std::optional<mesh::Mesh>& mesh,
                    const std::optional<octree::Octree>& tree, uint32_t iterations);

    // What SceneStage tells of its frames: the model and material of a frame it begins (before
    // beginning it), the settings it began with, and each finished frame it shows.
    void setFrameModel(const bssrdf::Model& model, const bssrdf::ParamValues& values,
                       const bssrdf::Builtins& builtins);
    void setFrameSettings(const render::Settings& settings) { m_frameSettings = settings; }
    void frameShown(int width, int height);
    // The model of the last frame begun; null before the first.
    const bssrdf::Model* frameModel() const { return m_frameModel ? &*m_frameModel : nullptr; }

    // What the B side renders: brute force of the shown frame's model (`model` null), or
    // another model rendered hierarchically with its own parameters and material.
    struct Request {
        const bssrdf::Model* model = nullptr;
        bssrdf::ParamValues values;
        bssrdf::Builtins builtins;
        std::string name; // what the B side shows (for the label)
    };
    // Starts a pass of the shown frame (a running one is dropped). Throws core::Error when no
    // frame is shown yet.
    void request(const Request& r);
    void requestBruteForce() { request({}); }
    // Advances the running pass by about budgetMs; true when it ended (done or failed: a
    // failure is problem()).
    bool advance(double budgetMs);
    bool running() const { return m_running; }

    // The brute-force pass's M per pixel, while its frame is the shown one.
    const std::vector<glm::vec4>* bruteForceResult() const;
    // The pass's tone-mapped image (RGBA8, row 0 at the top) and what it is, while its frame is
    // the shown one.
    const std::vector<unsigned char>* image() const;
    const std::string& name() const { return m_name; }
    // The last pass that failed, "" if none did.
    const std::string& problem() const { return m_problem; }

    // Hot reload and records of the renderer's programs (none before the first request).
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    shader::Records shaderRecords() const;

  private:
    std::filesystem::path m_root;
    const std::optional<mesh::Mesh>& m_mesh;
    const std::optional<octree::Octree>& m_tree;
    uint32_t m_iterations;
    // What the last frame was rendered with, and the shown frame's size and number.
    render::Settings m_frameSettings;
    std::optional<bssrdf::Model> m_frameModel;
    bssrdf::ParamValues m_frameValues;
    bssrdf::Builtins m_frameBuiltins;
    int m_shownWidth = 0, m_shownHeight = 0;
    long long m_shown = 0;
    std::unique_ptr<render::Renderer> m_renderer;
    std::vector<glm::vec4> m_exitance;
    std::vector<unsigned char> m_image;
    bool m_isBrute = true; // the pass is brute force of the frame
    std::string m_name;
    long long m_for = -1, m_doneFor = -1; // the shown frame a pass was started for / ended for
    bool m_running = false;
    std::string m_problem;
};

} // namespace app
