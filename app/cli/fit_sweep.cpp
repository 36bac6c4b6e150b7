// `fit --albedo-sweep`: a function fit. The free parameters are fitted at each reduced albedo
// α′ of a sweep (a medium with σ′t = 1/mm, σ′s = α′, σa = 1 − α′, the sweep's g and η; every
// length of the profile scales with 1/σ′t, so one σ′t serves all), each fit starting from the
// previous albedo's result. The result is the parameter as a table over the path-traced total
// diffuse reflectance A = 2π∫R_ref r dr per unit power entering (the "surface albedo" of
// Christensen & Burley 2015, whose s(A) curves were fitted this way by hand), written as
// sweep.csv, fit.json ("mode": "albedo_sweep") and report.md with the fitted values beside the
// published curves given with --published, and rel_err at the start and fitted values per albedo.
#include "cli/fit_command.h"
#include "cli/interrupt.h"

#include "common/exit_codes.h"
#include "core/core.h"
#include "core/text.h"
#include "gui/report_png.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A published curve: the value of one fitted variable against A.
struct Curve {
    std::string label; // the file's stem
    size_t variable = 0;
    std::vector<double> A, value;
};

// Reads "--published" CSV files: '#' lines are comments, the first other line is the header
// "A,LABEL" with LABEL a fitted variable, then rows "A,VALUE". Errors name file and line.
std::vector<Curve> readPublished(const std::vector<std::string>& files,
                                 const std::vector<FitVariable>& vars) {
    std::vector<Curve> out;
    for (const std::string& file : files) {
        std::string text;
        try {
            text = core::readFile(file);
        } catch (const core::Error&) {
            throw core::Error("--published", 0, "cannot read '" + file + "'");
        }
        Curve c;
        c.label = fs::path(file).stem().string();
        std::istringstream in(text);
        std::string line;
        bool header = false;
        for (int n = 1; std::getline(in, line); ++n) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            if (line.empty() || line[0] == '#') continue;
            const size_t comma = line.find(',');
            if (comma == std::string::npos || line.find(',', comma + 1) != std::string::npos)
                throw core::Error(file, n, "expected two columns separated by one comma");
            const std::string a = line.substr(0, comma), b = line.substr(comma + 1);
            if (!header) {
                header = true;
                size_t k = 0;
                while (k < vars.size() && vars[k].label != b)
                    ++k;
                if (a != "A" || k == vars.size()) {
                    std::string names;
                    for (const FitVariable& v : vars)
                        names += (names.empty() ? "" : ", ") + v.label;
                    throw core::Error(file, n,
                                      "the header must be 'A,PARAM' with PARAM one of the fitted "
                                      "variables (" +
                                          names + "), got '" + line + "'");
                }
                c.variable = k;
                continue;
            }
            char *ea = nullptr, *eb = nullptr;
            const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
            if (a.empty() || b.empty() || *ea || *eb || !std::isfinite(x) || !std::isfinite(y))
                throw core::Error(file, n, "'" + line + "' is not two numbers");
            if (!c.A.empty() && x <= c.A.back())
                throw core::Error(file, n, "A must increase from row to row");
            c.A.push_back(x);
            c.value.push_back(y);
        }
        if (c.A.empty()) throw core::Error(file, 0, "no rows after the header 'A,PARAM'");
        out.push_back(std::move(c));
    }
    return out;
}

struct SweepRow {
    double alphaPrime = 0, ldOverL = 0, A = NAN, ASe = NAN;
    FitOutcome fit;
};

std::string numText(double v, int digits = 6) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : std::string("nan");
}

std::string percent(double v) {
    return std::isfinite(v) ? core::formatNumber(100 * v, 3) + " %" : std::string("-");
}

// The fitted values of variable k against A (±2σ band), with the published curves of k.
std::string parameterPlot(const std::vector<SweepRow>& rows, const std::vector<FitVariable>& vars,
                          size_t k, const std::vector<Curve>& published, const FitArgs& a) {
    std::vector<plot::Series> series;
    plot::Series fitted;
    fitted.label = vars[k].label + " fitted +-2 sigma";
    fitted.color = 0xffffffff;
    fitted.marker = true;
    for (const SweepRow& r : rows) {
        if (!std::isfinite(r.A)) continue;
        const double v = r.fit.result.best[k], s = r.fit.sigma[k];
        fitted.x.push_back(r.A);
        fitted.y.push_back(v);
        fitted.bandLo.push_back(std::isfinite(s) ? v - 2 * s : v);
        fitted.bandHi.push_back(std::isfinite(s) ? v + 2 * s : v);
    }
    series.push_back(fitted);
    size_t colour = 0;
    for (const Curve& c : published) {
        if (c.variable != k) continue;
        plot::Series s;
        s.label = c.label;
        s.x = c.A;
        s.y = c.value;
        s.color = plot::defaultColor(colour++);
        s.dashed = true;
        series.push_back(s);
    }
    plot::Axis x{0, 1, plot::Scale::Linear, "A = total diffuse reflectance (path traced)"};
    plot::Axis y = plot::autoRange(series, plot::Scale::Linear, true);
    y.label = vars[k].label;
    return plotPng(640, 400, series, x, y, vars[k].label + " fitted at each albedo",
                   "eta " + core::formatNumber(a.sweepEta, 4) + ", g " +
                       core::formatNumber(a.sweepG, 3) + ", " + std::to_string(a.paths) +
                       " paths per albedo");
}

// rel_err at the start values and at the fitted ones against A (the θi = 0 target).
std::string relErrPlot(const std::vector<SweepRow>& rows, const std::vector<size_t>& target0) {
    plot::Series start, fitted;
    start.label = "rel_err at the start values";
    fitted.label = "rel_err fitted";
    start.color = plot::defaultColor(1);
    fitted.color = plot::defaultColor(0);
    start.dashed = true;
    for (size_t i = 0; i < rows.size(); ++i) {
        const SweepRow& r = rows[i];
        if (!std::isfinite(r.A)) continue;
        start.x.push_back(r.A);
        fitted.x.push_back(r.A);
        start.y.push_back(100 * r.fit.result.relErrStart[target0[i]]);
        fitted.y.push_back(100 * r.fit.result.relErrBest[target0[i]]);
    }
    const std::vector<plot::Series> series{start, fitted};
    plot::Axis x{0, 1, plot::Scale::Linear, "A = total diffuse reflectance (path traced)"};
    plot::Axis y = plot::autoRange(series, plot::Scale::Linear, true);
    y.lo = 0;
    y.label = "rel_err [%]";
    return plotPng(640, 400, series, x, y, "rel_err of the profile at normal incidence",
                   "over ln r in [0.1, 4] l_d, the reference's noise removed");
}

} // namespace

int runFitSweep(bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars, const FitArgs& a,
                const FitSettings& s) {
    for (double alpha : a.albedoSweep)
        if (!(std::isfinite(alpha) && alpha > 0 && alpha < 1))
            throw core::Error("--albedo-sweep", 0,
                              "reduced albedos must lie in (0, 1), got " + numText(alpha));
    size_t theta0 = 0;
    while (theta0 < a.thetaI.size() && a.thetaI[theta0] != 0)
        ++theta0;
    if (theta0 == a.thetaI.size())
        throw core::Error("--theta-i", 0,
                          "an albedo sweep needs 0 among its angles: A is the total diffuse "
                          "reflectance at normal incidence");
    const std::vector<Curve> published = readPublished(a.published, vars);

    std::vector<SweepRow> rows;
    std::vector<size_t> target0; // index of the θi = 0 target in each fit (one channel)
    for (double alpha : a.albedoSweep) {
        SweepRow row;
        row.alphaPrime = alpha;
        row.ldOverL = 1 / std::sqrt(3 * (1 - alpha));
        FitMedium m{"a' " + numText(alpha, 5), {}, {0}};
        m.params.sigmaS = glm::dvec3(alpha / (1 - a.sweepG));
        m.params.sigmaA = glm::dvec3(1 - alpha);
        m.params.g = a.sweepG;
        m.params.eta = a.sweepEta;
        row.fit = fitWithUncertainty(e, vars, {m}, a, s, " " + m.name);
        row.A = row.fit.targets[theta0].totalRd; // the θi = 0 target (one channel)
        row.ASe = row.fit.targets[theta0].totalRdSe;
        applyFit(vars, row.fit.result.best, e.values); // the next albedo starts here
        rows.push_back(std::move(row));
        target0.push_back(theta0);
        const FitOutcome& f = rows.back().fit;
        std::printf("a' %s  A %s:", numText(alpha, 5).c_str(), numText(rows.back().A, 5).c_str());
        for (size_t k = 0; k < vars.size(); ++k)
            std::printf(" %s = %s +- %s", vars[k].label.c_str(), numText(f.result.best[k]).c_str(),
                        numText(f.sigma[k], 2).c_str());
        std::printf("  rel_err %s -> %s\n", percent(f.result.relErrStart[theta0]).c_str(),
                    percent(f.result.relErrBest[theta0]).c_str());
        std::fflush(stdout);
        if (interrupted()) break;
    }

    // sweep.csv: one row per albedo
    std::ostringstream csv;
    csv << "# bssrdf-workbench fit --albedo-sweep: " << e.displayPath << ", eta " << a.sweepEta
        << ", g " << a.sweepG << ", sigma'_t = 1/mm, " << a.paths << " paths per albedo\n"
        << "alpha_prime,ld_over_l,A,A_se";
    for (const FitVariable& v : vars)
        csv << "," << v.label << "," << v.label << "_sigma";
    for (double t : a.thetaI) {
        const std::string at = a.thetaI.size() > 1 ? "_" + numText(t, 4) : "";
        csv << ",rel_err_start" << at << ",rel_err_fitted" << at;
    }
    csv << ",evaluations,converged\n";
    for (const SweepRow& r : rows) {
        csv << numText(r.alphaPrime, 9) << "," << numText(r.ldOverL, 9) << "," << numText(r.A, 9)
            << "," << numText(r.ASe, 3);
        for (size_t k = 0; k < vars.size(); ++k)
            csv << "," << numText(r.fit.result.best[k], 9) << "," << numText(r.fit.sigma[k], 3);
        for (size_t t = 0; t < a.thetaI.size(); ++t)
            csv << "," << numText(r.fit.result.relErrStart[t], 6) << ","
                << numText(r.fit.result.relErrBest[t], 6);
        csv << "," << r.fit.result.evaluations << "," << (r.fit.result.converged ? 1 : 0) << "\n";
    }
    const fs::path out(a.out);
    core::writeFile(out / "sweep.csv", csv.str());

    json j = {{"schema", "bssrdf-workbench-fit"},
              {"version", 1},
              {"mode", "albedo_sweep"},
              {"model", e.displayPath},
              {"objective", "mean over the targets of rel_err^2 (modules/core/relative_error.h)"},
              {"optimizer", "NLopt BOBYQA"},
              {"paths", a.paths},
              {"eta", a.sweepEta},
              {"g", a.sweepG},
              {"fixed", a.set},
              {"uncertainty", a.uncertainty ? kUncertaintyNote : "not computed (--no-uncertainty)"},
              {"sweep", json::array()}};
    bool allConverged = true;
    for (const SweepRow& r : rows) {
        json p = json::array();
        for (size_t k = 0; k < vars.size(); ++k)
            p.push_back(
                {{"name", vars[k].label},
                 {"start", r.fit.result.start[k]},
                 {"fitted", r.fit.result.best[k]},
                 {"sigma", std::isfinite(r.fit.sigma[k]) ? json(r.fit.sigma[k]) : json()},
                 {"halves",
                  r.fit.halfA.empty() ? json() : json::array({r.fit.halfA[k], r.fit.halfB[k]})}});
        json targets = json::array();
        for (size_t t = 0; t < a.thetaI.size(); ++t)
            targets.push_back({{"theta_i", a.thetaI[t]},
                               {"rel_err_start", r.fit.result.relErrStart[t]},
                               {"rel_err_fitted", r.fit.result.relErrBest[t]}});
        j["sweep"].push_back({{"alpha_prime", r.alphaPrime},
                              {"ld_over_l", r.ldOverL},
                              {"A", r.A},
                              {"A_se", r.ASe},
                              {"parameters", p},
                              {"targets", targets},
                              {"evaluations", r.fit.result.evaluations},
                              {"status", r.fit.result.status},
                              {"converged", r.fit.result.converged},
                              {"problems", r.fit.result.problems}});
        allConverged &= r.fit.result.converged;
    }
    core::writeFile(out / "fit.json", j.dump(2) + "\n");

    std::ostringstream md;
    md << "# Albedo sweep of " << e.displayPath << "\n\n"
       << "The free parameters fitted to the path-traced slab reference at each reduced albedo "
          "a' of a medium with sigma'_t = 1/mm (eta "
       << a.sweepEta << ", g " << a.sweepG << ", " << a.paths
       << " paths per albedo), by NLopt's BOBYQA minimising rel_err², each fit starting from the "
          "previous one. A is the reference's total diffuse reflectance per unit power "
          "entering; ± is "
       << (a.uncertainty ? kUncertaintyNote : "not computed (--no-uncertainty)") << ".";
    if (!a.set.empty()) {
        md << " Held fixed:";
        for (const std::string& f : a.set)
            md << " `" << f << "`";
        md << ".";
    }
    md << "\n\n| a' | l_d/l | A |";
    for (const FitVariable& v : vars)
        md << " " << v.label << " | ± |";
    md << " rel_err start | rel_err fitted |\n|---|---|---|";
    for (size_t k = 0; k < vars.size(); ++k)
        md << "---|---|";
    md << "---|---|\n";
    for (size_t i = 0; i < rows.size(); ++i) {
        const SweepRow& r = rows[i];
        md << "| " << numText(r.alphaPrime, 5) << " | " << numText(r.ldOverL, 4) << " | "
           << numText(r.A, 4) << " |";
        for (size_t k = 0; k < vars.size(); ++k)
            md << " " << numText(r.fit.result.best[k], 5) << " | " << numText(r.fit.sigma[k], 2)
               << " |";
        md << " " << percent(r.fit.result.relErrStart[target0[i]]) << " | "
           << percent(r.fit.result.relErrBest[target0[i]]) << " |\n";
    }
    if (a.plots && !rows.empty()) {
        md << "\n";
        for (size_t k = 0; k < vars.size(); ++k) {
            std::string file = "sweep_" + vars[k].label + ".png";
            for (char& c : file)
                if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_') c = '_';
            core::writeFile(out / file, parameterPlot(rows, vars, k, published, a));
            md << "![" << vars[k].label << " against A](" << file << ")\n";
        }
        core::writeFile(out / "sweep_rel_err.png", relErrPlot(rows, target0));
        md << "![rel_err against A](sweep_rel_err.png)\n";
    }
    md << "\nThe table as CSV: [sweep.csv](sweep.csv).\n";
    core::writeFile(out / "report.md", md.str());
    std::printf("wrote %s, %s, %s\n", (out / "sweep.csv").c_str(), (out / "fit.json").c_str(),
                (out / "report.md").c_str());
    if (interrupted()) {
        std::fprintf(stderr, "fit: interrupted: wrote the albedos fitted so far\n");
        return kInterrupted;
    }
    if (!allConverged) {
        std::fprintf(stderr,
                     "error: the fit did not converge at every albedo (converged 0 in sweep.csv; "
                     "the best points are written): raise --max-evaluations or narrow the "
                     "ranges\n");
        return kNotConverged;
    }
    return 0;
}

} // namespace app
