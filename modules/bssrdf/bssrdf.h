// bssrdf: the .bssrdf model file format (thesis Appendix A.2, "BSSRDF Interface").
//   A model is a text file: the first non-comment line lists attributes (analytic, radial, no_wi,
//   no_wo; 'analytic' is mandatory), followed by named sections `::begin NAME` ... `::end NAME`
//   in any order: 'parameters' (float/bool/color declarations exposed as uniforms),
//   'initializer' (GLSL, defines void init()), 'diffuseReflectance' (GLSL, defines
//   vec3 DiffuseReflectance(vec3 AlphaPrime), used for the R_dr/l_d inversion of thesis
//   Section 3.4), 'shader' (GLSL, defines vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo)),
//   or instead of 'shader' a 'table' naming data files (table_model.h), and 'sample' (GLSL, an
//   analytic radial sampler for the disk sampling of King et al. 2013: float SampleRadius(float
//   xi, int channel), float PdfRadius(float r, int channel), float MaxRadius(int channel)).
//   A shader section may also expose its profile as Gaussian lobes (int QdLobeCount(), vec2
//   QdLobe(int k, int channel)): both or neither.
//   Unknown sections are ignored with a note. Every format error throws core::Error carrying
//   the display path and the 1-based line it is about.
//   See materials/README.md for the full format, the built-ins and the unit conventions.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bssrdf {

enum class ParamType { Float, Bool, Color };

// One user parameter; becomes `uniform float|bool|vec3 NAME;` in every assembled shader.
struct Param {
    std::string name;
    ParamType type = ParamType::Float;
    float min = 0, max = 1;
    // default: Float -> value[0], Bool -> value[0] (0 or 1), Color -> rgb
    std::array<float, 3> value{};
    int line = 0; // 1-based line of the declaration in the model file
};

// A GLSL section, kept verbatim (CR stripped); every line ends with '\n'.
struct Section {
    std::string name;
    std::string code;
    int firstLine = 0; // 1-based file line of the first line of `code`
    int beginLine = 0; // 1-based file line of `::begin NAME`
};

struct Attributes {
    bool analytic = false, radial = false, noWi = false, noWo = false;
};

struct Model {
    std::string path;   // display path used in every message, e.g. "materials/dipole.bssrdf"
    std::string name;   // file stem, e.g. "dipole"
    std::string source; // full text
    std::string hash;   // core::hashHex(source)
    Attributes attrs;
    std::vector<Param> params;
    std::optional<Section> initializer, diffuseReflectance, shader;
    // The optional analytic radial sampler (`::begin sample`, materials/README.md).
    std::optional<Section> sample;
    // The file line of `vec2 QdLobe(` in the shader section when the model exposes its profile
    // as Gaussian lobes (QdLobeCount and QdLobe both defined), else 0.
    int lobesLine = 0;
    // A `table` section (table_model.h): the shader is generated from data files by loadModel.
    std::optional<Section> table;
    std::vector<std::filesystem::path> dataFiles; // the files a table model was made from
    struct TableMedium {
        double sigmaA = 0, sigmaS = 0, g = 0, eta = 1;
    };
    // For tables path-traced for one medium per channel: that medium (else empty).
    std::vector<TableMedium> tableMedia;
    std::vector<std::string> notes; // non-fatal notes, e.g. "file:7: unknown section 'foo' ignored"

    const Param* findParam(std::string_view n) const;
};

// Parses a model; throws core::Error(displayPath, line, message) on the first error.
Model parseModel(std::string_view text, const std::string& displayPath);
// core::readFile + parseModel; read errors are reported against displayPath too.
Model loadModel(const std::filesystem::path& file, const std::string& displayPath);
// Larger model files are refused by loadModel before they are read.
inline constexpr std::uintmax_t kMaxModelBytes = std::uintmax_t(4) << 20;

// Names a parameter may not take: the built-in uniforms and constant (SigmaA, SigmaS, G, IOR,
// Scale, PI) and the reserved function names (Bssrdf, DiffuseReflectance, init, main,
// SampleRadius, PdfRadius, MaxRadius, QdLobeCount, QdLobe).
const std::vector<std::string>& builtinNames();

// True for a valid parameter identifier: [A-Za-z_][A-Za-z0-9_]*, no "gl_" prefix, no "__",
// not a GLSL keyword. (Built-in clashes are checked separately.)
bool isValidIdentifier(std::string_view name);

} // namespace bssrdf
