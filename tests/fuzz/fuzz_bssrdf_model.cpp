// Fuzzes the .bssrdf model format: parseModel (attributes, sections, the parameters block), then
// for a parsed model its table expansion (data files resolved in an empty folder) and its part of
// the GLSL assembly (uniform declarations, modelExtension through shader::assemble) as text.
// Table models resolve their files in a folder holding one valid profile, p.csv.
#include "fuzz_common.h"

#include "bssrdf/assembly.h"
#include "bssrdf/bssrdf.h"
#include "bssrdf/table_model.h"

namespace {
const std::filesystem::path& modelDir() {
    static const std::filesystem::path dir = [] {
        std::filesystem::path d = fuzz::scratchDir() / "model";
        std::filesystem::create_directories(d);
        const std::string profile = "r_mm,R,G,B\n0,4,2,1\n1,2,1,0.5\n3,0,0.5,0.25\n";
        fuzz::writeInput(reinterpret_cast<const uint8_t*>(profile.data()), profile.size(),
                         "model/p.csv");
        return d;
    }();
    return dir;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::expectCleanError([&] {
        bssrdf::Model m = bssrdf::parseModel(fuzz::asText(data, size), "fuzz.bssrdf");
        if (m.table) bssrdf::expandTable(m, modelDir());
        (void)bssrdf::uniformDeclarations(m);
        const std::string tmpl = "#version 450\n#include \"prelude.glsl\"\n#pragma bssrdf_model\n"
                                 "void main() { init(); }\n";
        auto resolve = [](const std::string& name, std::string& display) {
            display = "shaders/" + name;
            return std::string("const float PI = 3.14159265;\n");
        };
        shader::AssembledShader s = bssrdf::assemble(tmpl, "fuzz.comp", &m, resolve);
        if (s.glsl.empty()) std::abort();
    });
    return 0;
}
