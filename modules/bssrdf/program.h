// bssrdf GPU half: builds one GL program per (model, consumer template) from
// shaders/<template> + the model's sections (see assembly.h), maps driver errors back to
// `materials/NAME.bssrdf:LINE`, sets built-in and user uniforms, and runs the two consumers
// of the foundation:
//   - pencil_profile.comp: the pencil-beam profile of thesis 3.6.3 — Bssrdf(Xi = 0,
//     Wi = n, Xo = (r,0,0), Wo = n) on a radius grid (mm) on the semi-infinite slab;
//   - invert_rdr.comp: DiffuseReflectance(α′) at a batch of α′ values, the inner step of the
//     GPU bisection of thesis 3.4;
//   - the pencil program's query modes: Bssrdf() at given directions, a model's analytic sampler
//     functions and its Gaussian lobes (sampler_queries.cpp).
#pragma once

#include "bssrdf/assembly.h"
#include "bssrdf/bssrdf.h"
#include "gl/gl.h"
#include "shader/program.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace bssrdf {

// Current values of a model's user parameters (Float: [0], Bool: [0] 0/1, Color: rgb).
using ParamValues = std::map<std::string, std::array<float, 3>>;
ParamValues defaultValues(const Model& m);
// Values that survive a reload: same name and same type; everything else takes the default.
ParamValues carryOver(const Model& newModel, const Model& oldModel, const ParamValues& old);
// The parameters whose value in use differs from the model file's default (a default edited in
// the file does not change a value that survived the reload): "Name" each, in file order.
std::vector<std::string> valuesOffTheDefaults(const Model& m, const ParamValues& v);

// Built-in uniforms every model sees (materials/README.md): σ in 1/mm, scale in mm/unit.
struct Builtins {
    glm::vec3 sigmaA{0.0f}, sigmaS{1.0f};
    float g = 0.0f, ior = 1.3f, scale = 1.0f;
};
// The description of Builtins' members (core/fields.h; cache keys).
template <class V> void fields(V& v, Builtins& b) {
    v("sigma_a", b.sigmaA, "σa, 1/mm");
    v("sigma_s", b.sigmaS, "σs, 1/mm");
    v("g", b.g, "mean cosine");
    v("ior", b.ior, "η");
    v("scale", b.scale, "mm per mesh unit");
}

// Assemble (shaders/<templateName> from `src` with the model) + compile + link; `record`
// gets the files read (template, includes, the model file) and counts the build. Throws
// core::Error(file, line, message) for the first error diagnostic; message carries every
// diagnostic; a link error without a location blames the model file.
gl::Program buildModelProgram(const Model& m, const std::string& templateName,
                              const shader::Sources& src, shader::Record& record);
gl::Program buildModelProgram(const Model& m, const std::string& templateName,
                              const shader::Sources& src);

void setUniforms(GLuint program, const Model& m, const ParamValues& values, const Builtins& b);

// Radius grid used by the pencil plot: `samples` radii from 0 to rMax (mm), inclusive.
std::vector<double> radiusGrid(double rMaxMm, int samples);

struct Profile {
    std::vector<double> r;         // mm
    std::vector<glm::dvec3> value; // Bssrdf() RGB, 1/mm² for the shipped models
};
// "" when every value of `p` is finite and >= 0, else what is not and where, e.g.
// "R(r) is NaN at 3 of 512 radii (r 0 to 0.039 mm, channel R); negative at 9 of 512 radii
// (r 2.3 to 4.1 mm, channels G B)" (profile_check.cpp). Such values are reported, never drawn
// or summed as if they were numbers.
std::string profileProblem(const Profile& p);
// Runs pencil_profile.comp. `program` must come from buildModelProgram(m, "pencil_profile.comp").
Profile evaluateProfile(GLuint program, const Model& m, const ParamValues& values,
                        const Builtins& b, const std::vector<double>& radii);

// Bssrdf(Xi = 0, Wi, Xo, Wo) at arbitrary geometry (mm, unit vectors) through the pencil
// program's query mode. Throws core::Error when the program is not built from a template
// with that mode.
struct Query {
    glm::vec3 xo{0.0f}, wi{0.0f, 0.0f, 1.0f}, wo{0.0f, 0.0f, 1.0f};
};
std::vector<glm::dvec3> evaluateQueries(GLuint program, const Model& m, const ParamValues& values,
                                        const Builtins& b, const std::vector<Query>& queries);

// The analytic radial sampler of a model with a `sample` section (materials/README.md) through
// the pencil program's query mode 2: each query calls one of its functions at x (ξ for
// SampleRadius, r in mm for PdfRadius, unused for MaxRadius) and channel 0, 1 or 2. Throws
// core::Error(m.path, 0, …) for a model without the section.
enum class SamplerFunction { SampleRadius = 0, PdfRadius = 1, MaxRadius = 2 };
struct SamplerQuery {
    SamplerFunction function = SamplerFunction::SampleRadius;
    double x = 0;
    int channel = 0;
};
std::vector<double> evaluateSampler(GLuint pencilProgram, const Model& m, const ParamValues& values,
                                    const Builtins& b, const std::vector<SamplerQuery>& queries);

// The Gaussian lobes of a model with the lobe interface (materials/README.md) through the
// pencil program's query mode 3: per channel, (weight, variance in mm²) of lobe k = 0 … count − 1.
// A count outside 1 … kMaxLobes is a core::Error(m.path, m.lobesLine, …); so is a model without
// the interface (line 0).
inline constexpr int kMaxLobes = 4096;
std::array<std::vector<glm::dvec2>, 3> evaluateLobes(GLuint pencilProgram, const Model& m,
                                                     const ParamValues& values, const Builtins& b);

// The total diffuse reflectance R_dr(α′) = 2π ∫ R(r) r dr of a model without a
// `diffuseReflectance` section, integrated numerically from its pencil-beam profile (the pencil
// program at normal incidence): R_dr is scale free, so each α′ (per channel) is evaluated at
// σ′t = 1 — σa = 1 − α′, σs = α′/(1 − g) — with g and η from `b`. The integral runs in ln r
// from 10⁻⁶ to r_max = min(10⁵, 60 l_d) mean free paths (l_d = 1/√(3(1 − α′))) on 2048 points
// by the trapezoid rule on R r², plus R(r_min) r_min²/2 below. `pencilProgram` must come from
// buildModelProgram(m, "pencil_profile.comp").
std::vector<glm::dvec3> integrateDiffuseReflectance(GLuint pencilProgram, const Model& m,
                                                    const ParamValues& values, const Builtins& b,
                                                    const std::vector<glm::dvec3>& alphaPrime);

// Runs invert_rdr.comp on a batch of α′ (one vec3 per entry) and returns R_dr(α′).
std::vector<glm::dvec3> evaluateDiffuseReflectance(GLuint program, const Model& m,
                                                   const ParamValues& values, const Builtins& b,
                                                   const std::vector<glm::dvec3>& alphaPrime);

} // namespace bssrdf
