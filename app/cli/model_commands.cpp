// `profile` (a model's pencil-beam profile as CSV) and `invert` (R_dr / l_d → σa, σs), on a
// headless GL context; `new-model` (a model to edit, made from another: pipeline/new_model.h).
#include "cli/model_commands.h"

#include "cli/args.h"
#include "cli/command.h"
#include "cli/options.h"
#include "cli/output.h"
#include "common/exit_codes.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pipeline/new_model.h"
#include "pipeline/pencil_series.h"
#include "pipeline/workbench.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {
std::string rgb(const glm::dvec3& v) {
    return core::formatNumber(v.x) + " " + core::formatNumber(v.y) + " " + core::formatNumber(v.z);
}

} // namespace

int runProfile(const fs::path& root, const ProfileArgs& a) {
    if (a.samples < 2) throw core::Error("--samples", 0, "must be >= 2");
    if (a.rMax && !(*a.rMax > 0 && std::isfinite(*a.rMax)))
        throw core::Error("--rmax", 0, "must be a positive length in mm");
    fs::path model = resolveModel(root, a.model);
    checkWritable(a.out, "--out");
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    wb.shared() = settingsFromArgs(wb, a.preset, a.sigmaA, a.sigmaS, a.g, a.eta);
    wb.plotSettings().samples = a.samples;
    if (a.rMax) {
        wb.plotSettings().fixedRange = true;
        wb.plotSettings().rMaxMm = *a.rMax;
    }
    wb.update();
    auto& v = wb.view(e.displayPath);
    if (!v.effective) throw core::Error(e.displayPath, 0, v.materialProblem);
    const auto& p = *v.effective;
    std::ostringstream out;
    out << "# bssrdf-workbench profile " << BW_VERSION << "\n"
        << "# model " << e.displayPath << " (" << e.model->hash << ")\n"
        << "# preset " << (wb.shared().preset.empty() ? "(none)" : wb.shared().preset) << "\n"
        << "# sigma_a " << rgb(p.sigmaA) << " 1/mm\n"
        << "# sigma_s " << rgb(p.sigmaS) << " 1/mm\n"
        << "# g " << core::formatNumber(p.g) << "\n# eta " << core::formatNumber(p.eta) << "\n"
        << "# r_max_mm " << core::formatNumber(wb.rMaxMm()) << "\n# samples " << a.samples << "\n";
    for (const auto& [k, val] : e.values)
        out << "# param " << k << " " << core::formatNumber(val[0]) << " "
            << core::formatNumber(val[1]) << " " << core::formatNumber(val[2]) << "\n";
    out << "# " << normalisationNote() << "\n";
    if (!v.profileProblem.empty()) out << "# invalid " << v.profileProblem << "\n";
    out << "r_mm,R,G,B\n";
    for (size_t i = 0; i < v.profile.r.size(); ++i)
        out << core::formatNumber(v.profile.r[i]) << ',' << core::formatNumber(v.profile.value[i].x)
            << ',' << core::formatNumber(v.profile.value[i].y) << ','
            << core::formatNumber(v.profile.value[i].z) << '\n';
    core::writeFile(a.out, out.str());
    std::cerr << "wrote " << a.out << " (" << v.profile.r.size() << " radii up to "
              << core::formatNumber(wb.rMaxMm()) << " mm)\n";
    if (!v.profileProblem.empty()) { // written, but not a valid reflectance: say so, status 3
        std::cerr << "error: " << e.displayPath << ": " << v.profileProblem << "\n";
        return kEnergyCheckFailed;
    }
    return 0;
}

int runInvert(const fs::path& root, const InvertArgs& a) {
    fs::path model = resolveModel(root, a.model);
    MaterialSettings s;
    s.mode = ParamMode::RdrLd;
    s.rdr = parseRgb(a.rdr, "--rdr");
    s.ld = parseRgb(a.ld, "--ld");
    if (a.g) s.params.g = *a.g;
    s.params.eta = a.eta.value_or(1.3);
    for (int c = 0; c < 3; ++c) {
        if (!(s.rdr[c] >= 0 && s.rdr[c] <= 1))
            throw core::Error("--rdr", 0,
                              "R_dr must lie in [0, 1], got " + core::formatNumber(s.rdr[c]));
        if (!(s.ld[c] > 0) || !std::isfinite(s.ld[c]))
            throw core::Error("--ld", 0,
                              "l_d must be a positive length in mm, got " +
                                  core::formatNumber(s.ld[c]));
    }
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    auto p = effectiveParams(e, s);
    std::printf("sigma_a %s\nsigma_s %s\n", rgb(p.sigmaA).c_str(), rgb(p.sigmaS).c_str());
    return 0;
}

Command newModelCommand() {
    return {"new-model", "a new model to edit: materials/NAME.bssrdf made from another", false,
            [](CLI::App& cmd) -> CommandRun {
                struct Args {
                    std::string name, from = kNewModelTemplate;
                };
                auto a = std::make_shared<Args>();
                // NAME alone (`new-model mine`) or --name NAME
                cmd.add_option("name,--name", a->name,
                               "the new model's name (materials/NAME.bssrdf)")
                    ->required();
                cmd.add_option("--from", a->from, "the model whose text it starts from")
                    ->capture_default_str();
                return [a](CommandContext& ctx) {
                    const fs::path from = resolveModel(ctx.root(), a->from, "--from");
                    if (std::string bad = newModelProblem(ctx.root(), a->name); !bad.empty())
                        throw core::Error("--name", 0, "'" + a->name + "': " + bad);
                    const fs::path file = createModel(ctx.root(), a->name, from);
                    std::printf("wrote %s (from %s): edit it and save; a running workbench loads "
                                "it as it appears and at every save\n",
                                file.c_str(), from.c_str());
                    return 0;
                };
            }};
}

Command profileCommand() {
    return {
        "profile", "pencil-beam profile of a model as CSV", false, [](CLI::App& cmd) -> CommandRun {
            auto a = std::make_shared<ProfileArgs>();
            cmd.add_option("--model", a->model, ".bssrdf file")->required();
            cmd.add_option("--preset", a->preset, "Jensen et al. 2001 preset (sigma_s', sigma_a)");
            cmd.add_option("--sigma-a", a->sigmaA, "absorption R,G,B in 1/mm");
            cmd.add_option("--sigma-s", a->sigmaS, "scattering R,G,B in 1/mm");
            const material::MaterialParams materialDefaults;
            const PlotSettings plotDefaults;
            a->samples = plotDefaults.samples;
            cmd.add_option("--g", a->g,
                           "mean cosine (default " + defaultText(materialDefaults.g) + ")");
            cmd.add_option("--eta", a->eta,
                           "relative index of refraction (default " +
                               defaultText(materialDefaults.eta) + ")");
            // the plot's own ranges (PlotSettings' description), as in the GUI and captures
            addNumberOption(&cmd, "--rmax", a->rMax,
                            "largest radius in mm (default " + defaultText(plotDefaults.rangeLd) +
                                " x largest l_d)",
                            core::limitsOf<PlotSettings>("r_max_mm"));
            addCountOption(&cmd, "--samples", a->samples,
                           "number of radii (default " + std::to_string(plotDefaults.samples) + ")",
                           core::limitsOf<PlotSettings>("samples"));
            cmd.add_option("--out", a->out, "CSV file: # header, then r_mm,R,G,B")->required();
            return [a](CommandContext& ctx) { return runProfile(ctx.root(), *a); };
        }};
}

Command invertCommand() {
    return {
        "invert", "R_dr / l_d -> sigma_a, sigma_s (1/mm)", false, [](CLI::App& cmd) -> CommandRun {
            auto a = std::make_shared<InvertArgs>();
            const material::MaterialParams materialDefaults;
            cmd.add_option("--model", a->model, ".bssrdf file with a diffuseReflectance section")
                ->required();
            cmd.add_option("--rdr", a->rdr, "total diffuse reflectance R,G,B in [0,1]")->required();
            cmd.add_option("--ld", a->ld, "diffuse mean free path R,G,B in mm")->required();
            cmd.add_option("--g", a->g,
                           "mean cosine (default " + defaultText(materialDefaults.g) + ")");
            cmd.add_option("--eta", a->eta,
                           "relative index of refraction (default " +
                               defaultText(materialDefaults.eta) + ")");
            return [a](CommandContext& ctx) { return runInvert(ctx.root(), *a); };
        }};
}

} // namespace app
