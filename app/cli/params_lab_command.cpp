// `bssrdf-workbench params-lab`: the parameterization lab (pipeline/params_lab.h). Every artist
// mapping of pipeline/param_mappings.h at every asked albedo, η and g, path traced. Writes
// DIR/lab.csv (one row per case), DIR/report.md (the mappings with their sources, the worst
// albedo error at normal incidence and under diffuse light and the spread of r̄/d per mapping,
// η and g) and per mapping DIR/<id>_albedo.png and <id>_albedo_diffuse.png (measured A against
// asked A, one curve per η and g) and DIR/<id>_radius.png (r̄/d against A).
#include "cli/args.h"
#include "cli/command.h"
#include "cli/interrupt.h"
#include "cli/options.h"
#include "cli/output.h"

#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "gui/report_png.h"
#include "pipeline/params_lab.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {

struct LabArgs {
    LabSettings lab;
    std::string out;
};

std::string labNumber(double v, int digits = 6) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : std::string("nan");
}

// One mapping's two pictures: measured A against asked A, and r̄/d against A; a curve per (η, g).
void writePlots(const fs::path& dir, const std::string& id, const std::vector<LabCase>& cases) {
    std::map<std::pair<double, double>, std::pair<plot::Series, plot::Series>> curves;
    std::map<std::pair<double, double>, plot::Series> diffuse;
    for (const LabCase& c : cases) {
        if (c.mapping != id || !std::isfinite(c.measured)) continue;
        if (std::isfinite(c.diffuse)) {
            plot::Series& d = diffuse[{c.eta, c.g}];
            d.x.push_back(c.albedo);
            d.y.push_back(c.diffuse);
            d.bandLo.push_back(c.diffuse - 2 * c.diffuseSe);
            d.bandHi.push_back(c.diffuse + 2 * c.diffuseSe);
        }
        auto& [albedo, radius] = curves[{c.eta, c.g}];
        albedo.x.push_back(c.albedo);
        albedo.y.push_back(c.measured);
        albedo.bandLo.push_back(c.measured - 2 * c.measuredSe);
        albedo.bandHi.push_back(c.measured + 2 * c.measuredSe);
        radius.x.push_back(c.albedo);
        radius.y.push_back(c.meanRadiusMm / c.lengthMm);
    }
    std::vector<plot::Series> a, r;
    plot::Series asked;
    asked.label = "asked";
    asked.x = {0, 1};
    asked.y = {0, 1};
    asked.color = 0xffffffff;
    asked.dashed = true;
    a.push_back(asked);
    size_t k = 0;
    for (auto& [key, pair] : curves) {
        const std::string label =
            "eta " + core::formatNumber(key.first, 3) + ", g " + core::formatNumber(key.second, 3);
        pair.first.label = pair.second.label = label;
        pair.first.color = pair.second.color = plot::defaultColor(k);
        pair.second.dashed = pair.first.dashed = key.second != 0;
        ++k;
        a.push_back(pair.first);
        r.push_back(pair.second);
    }
    plot::Axis x{0, 1, plot::Scale::Linear, "asked albedo A"};
    plot::Axis ya{0, 1, plot::Scale::Linear, "measured R_d / (1 - R_sp)"};
    core::writeFile(dir / (id + "_albedo.png"),
                    plotPng(640, 400, a, x, ya, id + ": the albedo it gives",
                            "path traced, band +-2 se; dashed: g > 0"));
    if (!diffuse.empty()) {
        std::vector<plot::Series> ad{asked};
        size_t j = 0;
        for (auto& [key, series] : diffuse) {
            series.label = "eta " + core::formatNumber(key.first, 3) + ", g " +
                           core::formatNumber(key.second, 3);
            series.color = plot::defaultColor(j++);
            series.dashed = key.second != 0;
            ad.push_back(series);
        }
        plot::Axis yd{0, 1, plot::Scale::Linear, "measured albedo under diffuse light"};
        core::writeFile(dir / (id + "_albedo_diffuse.png"),
                        plotPng(640, 400, ad, x, yd,
                                id + ": the albedo it gives under diffuse light",
                                "8 incidence angles (Gauss-Legendre in cos), band +-2 se"));
    }
    plot::Axis yr = plot::autoRange(r, plot::Scale::Linear, true);
    yr.lo = std::min(yr.lo, 0.0);
    yr.label = "mean exit radius / d";
    core::writeFile(dir / (id + "_radius.png"),
                    plotPng(640, 400, r, x, yr, id + ": the radius it gives",
                            "mean exit radius over [0, 4.5 l_d) in units of the asked length"));
}

int runLab(const fs::path& root, const LabArgs& a) {
    if (a.out.empty()) throw core::Error("--out", 0, "give the folder to write");
    for (double v : a.lab.albedos)
        if (!(v > 0 && v < 1))
            throw core::Error("--albedos", 0, "albedos must lie in (0, 1), got " + labNumber(v));
    for (double v : a.lab.etas)
        if (!(v >= 1 && v <= 3))
            throw core::Error("--eta", 0, "eta must lie in [1, 3], got " + labNumber(v));
    for (double v : a.lab.gs)
        if (!(std::abs(v) < 0.95))
            throw core::Error("--g", 0, "g must lie in (-0.95, 0.95), got " + labNumber(v));
    if (a.lab.albedos.empty() || a.lab.etas.empty() || a.lab.gs.empty())
        throw core::Error("--albedos", 0, "give at least one albedo, eta and g");
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec || !fs::is_directory(a.out))
        throw core::Error("--out", 0, "cannot create the folder '" + a.out + "'");
    checkWritable((fs::path(a.out) / "lab.csv").string(), "--out");

    auto ctx = gl::createHeadlessContext(false);
    std::vector<fs::path> models;
    for (const ParamMapping& m : paramMappings())
        if (!m.model.empty()) models.push_back(root / m.model);
    Workbench wb(root, false, models);
    for (const auto& e : wb.library().entries())
        if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    core::Stopwatch clock;
    const std::vector<LabCase> cases = runParamsLab(
        wb, a.lab,
        [&](size_t done, size_t total) {
            core::progress("params-lab: %zu of %zu cases", done, total);
        },
        interruptFlag());
    core::progressEnd();

    const fs::path out(a.out);
    std::ostringstream csv;
    csv << "mapping,eta,g,A,d_mm,sigma_a,sigma_s,A_measured,A_measured_se,A_ratio,"
           "A_diffuse,A_diffuse_se,A_diffuse_ratio,mean_radius_mm,mean_radius_over_d,problem\n";
    for (const LabCase& c : cases)
        csv << c.mapping << "," << c.eta << "," << c.g << "," << c.albedo << "," << c.lengthMm
            << "," << labNumber(c.sigmaA, 9) << "," << labNumber(c.sigmaS, 9) << ","
            << labNumber(c.measured, 9) << "," << labNumber(c.measuredSe, 3) << ","
            << labNumber(c.measured / c.albedo, 6) << "," << labNumber(c.diffuse, 9) << ","
            << labNumber(c.diffuseSe, 3) << "," << labNumber(c.diffuse / c.albedo, 6) << ","
            << labNumber(c.meanRadiusMm, 6) << "," << labNumber(c.meanRadiusMm / c.lengthMm, 6)
            << ",\"" << core::printableText(c.problem) << "\"\n";
    core::writeFile(out / "lab.csv", csv.str());

    std::ostringstream md;
    md << "# Parameterization lab\n\nEach mapping turns an asked albedo A and length d = "
       << a.lab.lengthMm << " mm into sigma_a, sigma_s; the path tracer (" << a.lab.paths
       << " paths per case, normal incidence, the scoreboard's slab) measures the albedo it "
          "really gives, R_d/(1 - R_sp), at normal incidence and under uniform diffuse light, and "
          "its mean exit radius. `worst |A_meas/A - 1|` is "
          "over the asked albedos; `r/d` is the mean exit radius in units of d, lowest and "
          "highest over the albedos (a length that means one thing keeps it constant).\n\n"
          "| mapping | source | d means |\n|---|---|---|\n";
    for (const ParamMapping& m : paramMappings())
        md << "| " << m.id << " | " << m.source << " | " << m.length << " |\n";
    md << "\n| mapping | eta | g | worst, normal incidence | at A | worst, diffuse light | at A "
          "| r/d from | to | problems |\n|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<std::tuple<std::string, double, double>, std::vector<const LabCase*>> groups;
    for (const LabCase& c : cases)
        groups[{c.mapping, c.eta, c.g}].push_back(&c);
    for (const auto& [key, list] : groups) {
        double worst = -1, at = NAN, worstD = -1, atD = NAN, rlo = INFINITY, rhi = -INFINITY;
        int problems = 0;
        for (const LabCase* c : list) {
            if (!c->problem.empty()) {
                ++problems;
                continue;
            }
            const double e = std::abs(c->measured / c->albedo - 1);
            if (e > worst) worst = e, at = c->albedo;
            const double ed = std::abs(c->diffuse / c->albedo - 1);
            if (std::isfinite(ed) && ed > worstD) worstD = ed, atD = c->albedo;
            rlo = std::min(rlo, c->meanRadiusMm / c->lengthMm);
            rhi = std::max(rhi, c->meanRadiusMm / c->lengthMm);
        }
        md << "| " << std::get<0>(key) << " | " << std::get<1>(key) << " | " << std::get<2>(key)
           << " | " << (worst >= 0 ? core::formatNumber(100 * worst, 3) + " %" : "-") << " | "
           << labNumber(at, 3) << " | "
           << (worstD >= 0 ? core::formatNumber(100 * worstD, 3) + " %" : "-") << " | "
           << labNumber(atD, 3) << " | " << labNumber(rlo, 3) << " | " << labNumber(rhi, 3) << " | "
           << problems << " |\n";
    }
    md << "\n";
    for (const ParamMapping& m : paramMappings()) {
        if (std::none_of(cases.begin(), cases.end(),
                         [&](const LabCase& c) { return c.mapping == m.id; }))
            continue;
        writePlots(out, m.id, cases);
        md << "![" << m.id << ": albedo](" << m.id << "_albedo.png)\n";
        if (a.lab.diffuse)
            md << "![" << m.id << ": albedo under diffuse light](" << m.id
               << "_albedo_diffuse.png)\n";
        md << "![" << m.id << ": radius](" << m.id << "_radius.png)\n";
    }
    bool anyProblem = false;
    for (const LabCase& c : cases)
        if (!c.problem.empty()) {
            if (!anyProblem) md << "\nCases the mapping could not make:\n\n";
            anyProblem = true;
            md << "- " << c.mapping << " A " << c.albedo << " eta " << c.eta << " g " << c.g << ": "
               << c.problem << "\n";
        }
    md << "\nAll cases as CSV: [lab.csv](lab.csv).\n";
    core::writeFile(out / "report.md", md.str());
    std::printf("%zu cases in %.1f s: wrote %s, %s\n", cases.size(), clock.ms() / 1000,
                (out / "lab.csv").c_str(), (out / "report.md").c_str());
    if (interrupted()) {
        std::fprintf(stderr, "params-lab: interrupted: wrote the cases done so far\n");
        return kInterrupted;
    }
    return 0;
}

} // namespace

Command paramsLabCommand() {
    return {
        "params-lab",
        "measure what each artist mapping (albedo + length -> sigma) gives, path traced", false,
        [](CLI::App& cmd) -> CommandRun {
            auto a = std::make_shared<LabArgs>();
            std::string known;
            for (const ParamMapping& m : paramMappings())
                known += (known.empty() ? "" : ", ") + m.id;
            cmd.add_option("--mappings", a->lab.mappings,
                           "mappings to measure (default all: " + known + ")")
                ->delimiter(',');
            cmd.add_option("--albedos", a->lab.albedos,
                           "asked albedos in (0, 1) (default 0.1,0.3,0.5,0.7,0.9)")
                ->delimiter(',');
            cmd.add_option("--eta", a->lab.etas,
                           "relative indices of refraction (default 1,1.3,1.5)")
                ->delimiter(',');
            cmd.add_option("--g", a->lab.gs, "Henyey-Greenstein g values (default 0,0.8)")
                ->delimiter(',');
            cmd.add_flag("!--no-diffuse", a->lab.diffuse,
                         "skip the albedo under diffuse light (8 incidence angles per case)");
            addNumberOption(&cmd, "--length", a->lab.lengthMm,
                            "the asked length d in mm (default 1)", core::Limits{1e-6, 1e6});
            addCountOption(&cmd, "--paths", a->lab.paths,
                           "reference paths per case (default " + std::to_string(kLabPaths) + ")",
                           core::Limits{1000, 1e12});
            cmd.add_option("--out", a->out, "output folder: lab.csv, report.md, plots")->required();
            return [a](CommandContext& ctx) { return runLab(ctx.root(), *a); };
        }};
}

} // namespace app
