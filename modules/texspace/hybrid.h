// texspace/hybrid: the hybrid local/global method of seed 004 §3.3 (Chang 2007, after Mertens et
// al. 2003 and Dachsbacher & Stamminger 2003): R_d is split by a weighting function into a local
// part, integrated on the light's projection plane by a ring filter around each outgoing point,
// and a global part, integrated by texture-space importance sampling (pipeline.h).
//   Weighting (§3.3.1), r = |x_i − x_o| in mm, per channel:
//       W_l(r) = 1 − ½·e^{(r − R_p)·K}   for r ≤ R_p,       W_l(r) = ½·e^{−(r − R_p)·K}   for r >
//       R_p, W_g(r) = 1 − W_l(r),
//     so W_l(0) ≈ 1, W_l(R_p) = ½ and W_l is C¹ there (both sides have slope −K/2). (The thesis
//     prints e^{−(r−R_p)K} on both branches; on r ≤ R_p that would make W_l negative near 0,
//     contradicting its Fig. 3.4, so the exponent's sign there is taken as (r − R_p).) K = 1.5/mm.
//     B(x_o) = ∫ E R_d W_l dA + ∫ E R_d W_g dA = B_l + B_g exactly.
//   R_p: the largest r where the importance function R_d(r)·2πr meets the lower bound (0.1/mm in
//     the thesis), per channel, from the model's profile table (linear between entries); 0 when
//     the importance never reaches the bound (then everything but W_l's tail is global).
//     Checked against the thesis's Fig. 3.4: skim milk red (Jensen et al. 2001's σ_a = 0.0014,
//     σ′_s = 0.70 /mm, η 1.3; the caption's σ_a = 0.0024 gives 2.375) has R_p = 2.4141 mm.
//   Local term (§3.3.2, "local translucent shadow map"): the mesh rasterised from the directional
//     light (orthographic, irradiance/light_frame.h) into a map of first-hit positions and
//     normals. On the light's projection plane P the transmitted irradiance per unit area of P is
//     E0·Ft(η, n·L) (E_t dA = E0 Ft cosθ dA = E0 Ft dP), so
//         B_l(x_o) = ∫_P E0 Ft(η, n_i·L) R_d(|x_i − x_o|) W_l(|x_i − x_o|) dP,
//     x_i the surface point the map holds at that place of P (lit surface only: what the light
//     does not see has E_t = 0). The integral is a ring filter around x_o's projection: L rings
//     of C taps plus the centre (Fig. 3.9), radii by importance on the plane (the mixture over
//     the channels of R_d·W_l·2πr, each channel normalised, CDF F): L + 1 strata of equal
//     importance; the centre tap stands for the disk [0, b_0], F(b_0) = 1/(L+1); ring j's C taps
//     sit at the radius r_j of the stratum's middle quantile, F(r_j) = (j + ½)/(L+1), each
//     standing for the area 1/((L+1)·C·p(r_j)) with p(r) = f(r)/(2πr·∫f) the importance per unit
//     area — Dachsbacher & Stamminger's sampling on the plane, stratified (rings j turned by
//     j·π/C so taps do not line up). A deterministic quadrature in the CDF's variable: exact for
//     an integrand shaped like the importance, its error falls as L grows.
//   The global term is the texture-space estimator with R_d·W_g (render.h RadialWeight), so the
//   hybrid's variance is the global term's alone.
#pragma once

#include "core/limits.h"
#include "gl/gl.h"
#include "gl/vertex_snap.h"
#include "irradiance/light_frame.h"
#include "mesh/mesh.h"
#include "render/profile_table.h"
#include "shader/program.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <vector>

namespace texspace {

struct HybridSettings {
    float k = 1.5f;          // K of the weighting function, 1/mm
    float lowerBound = 0.1f; // importance lower bound of R_p, 1/mm
    int rings = 16;          // L
    int perRing = 8;         // C (Fig. 3.9 shows 4×4 + 1: ~20 % off on a plane; 16×8 + 1: ~2 %)
    int lightMapSize = 1024; // texels per side of the light-view map
};
template <class V> void fields(V& v, HybridSettings& s) {
    v("k", s.k, "K of the local/global weighting function, 1/mm", core::Limits{1e-3, 1e3});
    v("lower_bound", s.lowerBound, "importance lower bound that places R_p, 1/mm",
      core::Limits{1e-9, 1e3});
    v("rings", s.rings, "local filter rings L", core::Limits{1, 64});
    v("per_ring", s.perRing, "local filter taps per ring C", core::Limits{1, 64});
    v("light_map_size", s.lightMapSize, "light-view map texels per side", core::Limits{16, 4096});
}
// Throws core::Error("hybrid", 0, …) naming the setting.
void validateHybrid(const HybridSettings& s);

double localWeight(double r, double rp, double k); // W_l
// R_p per channel (mm) from the profile table; 0 where R·2πr never reaches `bound`.
glm::vec3 findRp(const render::ProfileTable& t, double bound);
// The same for one channel's profile R at ascending radii r (mm): the last crossing, linear.
double findRp(const std::vector<double>& r, const std::vector<double>& R, double bound);

struct RingTap {
    glm::vec2 offsetMm; // on the light's projection plane
    float areaMm2;      // the part of the plane it stands for
};
// The filter of L rings × C taps + the centre (see above); empty when R_d·W_l has no weight.
std::vector<RingTap> ringFilter(const render::ProfileTable& t, const glm::vec3& rp, double k,
                                int rings, int perRing);

// The light-view map and the local term on the GPU (shaders/hybrid_local.comp); needs a current
// OpenGL 4.5 context.
class LocalTerm {
  public:
    explicit LocalTerm(const shader::Sources& src); // builds the programs
    ~LocalTerm();
    LocalTerm(const LocalTerm&) = delete;
    LocalTerm& operator=(const LocalTerm&) = delete;

    void setMesh(const mesh::Mesh& m); // vertex normals computed when the mesh has none
    // Rasterises the mesh from the light (towards-light direction `towardsLight`) into
    // size × size texels; `shift`: the image moved by that many texels (an emulated other
    // rasteriser, as irradiance::ShadowMaps::render's).
    void renderLightMap(const glm::vec3& towardsLight, int size, glm::vec2 shift = glm::vec2(0.0f));
    // The taps read the map `shift` texels aside from the next dispatch on (an emulated other
    // driver's rounding of the tap's place: Pipeline::localSpread, tests); 0 by default.
    void setLookupShift(glm::vec2 shift) { m_lookupShift = shift; }
    // The map drawn with every vertex moved on its own from the next renderLightMap on (another
    // rasteriser emulated: gl::VertexSnap; tests); {} by default.
    void setVertexSnap(const gl::VertexSnap& snap) { m_snap = snap; }
    const irradiance::LightFrame& frame() const { return m_frame; }
    // B_l and L_o = Ft(η, cos θo)/π · B_l per pixel of the G-buffer (positions and normals of a
    // render::Frame), rgb and w = hit, row-major as the renderer's read-back.
    struct Result {
        std::vector<glm::vec4> exitance, radiance;
    };
    // begin uploads the inputs, step(rows) evaluates the next `rows` rows of pixels (one
    // dispatch; true when every row is done), result() reads the whole image back; evaluate
    // does all three. The G-buffer textures must keep their content until the last step.
    void begin(GLuint gPosition, GLuint gNormal, int width, int height,
               const glm::vec3& cameraPosition, const render::ProfileTable& table,
               const std::vector<RingTap>& taps, const glm::vec3& rp, float k,
               const glm::vec3& irradiance, float ior, float scaleMm);
    bool step(int rows);
    Result result() const;
    Result evaluate(GLuint gPosition, GLuint gNormal, int width, int height,
                    const glm::vec3& cameraPosition, const render::ProfileTable& table,
                    const std::vector<RingTap>& taps, const glm::vec3& rp, float k,
                    const glm::vec3& irradiance, float ior, float scaleMm);
    // Per tap, for the allowance of another driver's map (local_spread.cpp), after begin():
    // beginTaps keeps each tap's L_o term at the listed pixels (row-major indices) as the map and
    // lookups are now; raiseTaps(group) raises each tap's spread of `group` (0, 1) to how far its
    // term moved with the map and lookups as they are then; tapSpreads() reads, per listed pixel,
    // Σ_taps (spread of group 0 + spread of group 1). tapsPerPass(): how many pixels one pass may
    // list within the storage block limit.
    void beginTaps(const std::vector<uint32_t>& pixels);
    void raiseTaps(int group);
    std::vector<glm::vec3> tapSpreads() const;
    size_t tapsPerPass() const;
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    shader::Records records() const;
    GLuint lightPositionTexture() const { return m_lightPosition.id(); }

  private:
    void bindInputs(int mode) const; // hybrid_local.comp's program, inputs and LocalTapMode
    shader::Sources m_src;
    shader::Record m_mapRecord, m_localRecord;
    gl::Program m_mapProgram, m_localProgram;
    gl::Buffer m_vertices, m_indices;
    gl::VertexArray m_vao;
    GLsizei m_indexCount = 0;
    mesh::Mesh m_mesh;
    irradiance::LightFrame m_frame;
    gl::Texture m_lightPosition, m_lightNormal, m_lightDepth;
    gl::FramebufferId m_fbo;
    int m_mapSize = 0;
    glm::vec2 m_lookupShift{0.0f};
    gl::VertexSnap m_snap;
    // the evaluation in progress (begin / step)
    gl::Buffer m_tableBuffer, m_tapBuffer, m_exitance, m_radiance; // hybrid_local.comp's results
    gl::Buffer m_tapPixels, m_tapOwn, m_tapSpread;                 // beginTaps / raiseTaps
    size_t m_tapPixelCount = 0;
    GLuint m_gPosition = 0, m_gNormal = 0;
    int m_width = 0, m_height = 0, m_row = 0, m_tapCount = 0;
};

} // namespace texspace
