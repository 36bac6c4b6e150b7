// Fitting a model's parameters to the reference (fitting.h).
#include "pipeline/fitting.h"

#include "core/core.h"
#include "core/relative_error.h"
#include "core/text.h"
#include "pipeline/model_stages.h"
#include "pipeline/scoring.h"
#include "pipeline/scoring_oblique.h"
#include "pipeline/slice_model.h"

#include <nlopt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>

namespace app {

namespace {

// The parameter `name` of m; throws core::Error(arg, …) listing the declared ones when m has none
// of that name.
const bssrdf::Param* declaredParam(const bssrdf::Model& m, const std::string& name,
                                   const std::string& arg) {
    if (const bssrdf::Param* p = m.findParam(name)) return p;
    std::string known;
    for (const auto& q : m.params)
        known += (known.empty() ? "" : ", ") + q.name;
    throw core::Error(arg, 0,
                      "'" + name + "' is not a parameter of " + m.path +
                          (known.empty() ? " (it declares none)" : " (it declares " + known + ")"));
}

double parseBound(const std::string& text, const std::string& what) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw core::Error("--params", 0, what + ": '" + text + "' is not a number");
    return v;
}

const char* stopReason(nlopt_result r) {
    switch (r) {
    case NLOPT_SUCCESS:
        return "success";
    case NLOPT_STOPVAL_REACHED:
        return "objective reached the stop value";
    case NLOPT_FTOL_REACHED:
        return "objective changed less than its tolerance";
    case NLOPT_XTOL_REACHED:
        return "parameters changed less than their tolerance (converged)";
    case NLOPT_MAXEVAL_REACHED:
        return "evaluation budget spent before converging";
    case NLOPT_MAXTIME_REACHED:
        return "time limit reached before converging";
    case NLOPT_FORCED_STOP:
        return "stopped (cancelled): the best point so far";
    case NLOPT_ROUNDOFF_LIMITED:
        return "stopped by roundoff: the best point so far";
    case NLOPT_OUT_OF_MEMORY:
        return "out of memory";
    case NLOPT_INVALID_ARGS:
        return "invalid arguments";
    case NLOPT_FAILURE:
    default:
        return "the optimizer failed";
    }
}

struct Objective {
    const std::vector<FitVariable>* vars;
    const ObjectiveFn* fn;
    int evaluations = 0;
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> bestX;
    std::vector<std::string> problems;
    const std::function<void(int, double)>* progress;
    const std::atomic<bool>* cancel;
    nlopt_opt opt = nullptr;
    size_t notFinite = 0; // evaluations where the model was not finite
};

// The radical inverse of k in `base` (the Halton sequence's coordinate), in [0, 1).
double halton(int k, int base) {
    double f = 1, r = 0;
    for (; k > 0; k /= base) {
        f /= base;
        r += f * (k % base);
    }
    return r;
}
constexpr std::array<int, 8> kPrimes{2, 3, 5, 7, 11, 13, 17, 19};

double objective(unsigned n, const double* x, double*, void* data) {
    auto& o = *static_cast<Objective*>(data);
    if (o.cancel && o.cancel->load()) {
        if (o.opt) nlopt_force_stop(o.opt);
        return std::numeric_limits<double>::max();
    }
    std::string problem;
    double f = (*o.fn)(std::vector<double>(x, x + n), problem);
    if (o.cancel && o.cancel->load()) { // cancelled while it evaluated: not a model problem
        if (o.opt) nlopt_force_stop(o.opt);
        return std::numeric_limits<double>::max();
    }
    if (!std::isfinite(f)) {
        // outside where the model is finite: the worst value there is, and a note of where
        ++o.notFinite;
        if (o.problems.size() < 20) {
            std::string at;
            for (unsigned i = 0; i < n; ++i)
                at += (i ? ", " : "") + (*o.vars)[i].label + " = " + core::formatNumber(x[i], 6);
            o.problems.push_back(at + ": " + (problem.empty() ? "no finite rel_err" : problem));
        }
        f = std::numeric_limits<double>::max();
    }
    ++o.evaluations;
    if (f < o.best) {
        o.best = f;
        o.bestX.assign(x, x + n);
    }
    if (o.progress && *o.progress) (*o.progress)(o.evaluations, o.best);
    return f;
}

} // namespace

std::vector<FitVariable> fitVariables(const bssrdf::Model& m,
                                      const std::vector<std::string>& names) {
    std::vector<FitVariable> out;
    std::set<std::string> seen;
    for (const std::string& spec : names) {
        const size_t eq = spec.find('=');
        const std::string name = spec.substr(0, eq);
        if (name == kSigmaScale || name == kMediumG) { // the medium the model is evaluated with
            if (!seen.insert(name).second)
                throw core::Error("--params", 0, "'" + name + "' is given twice");
            const bool scale = name == kSigmaScale;
            const double declaredLo = scale ? 0.1 : -0.95, declaredHi = scale ? 10.0 : 0.95;
            double lo = declaredLo, hi = declaredHi;
            if (eq != std::string::npos) {
                const std::string range = spec.substr(eq + 1);
                const size_t comma = range.find(',');
                if (comma == std::string::npos)
                    throw core::Error("--params", 0, "'" + spec + "': expected NAME=LO,HI");
                lo = parseBound(range.substr(0, comma), name + " lower bound");
                hi = parseBound(range.substr(comma + 1), name + " upper bound");
                if (lo < declaredLo || hi > declaredHi || !(lo < hi))
                    throw core::Error("--params", 0,
                                      "'" + spec + "': the range must lie inside [" +
                                          core::formatNumber(declaredLo, 3) + ", " +
                                          core::formatNumber(declaredHi, 3) + "] with LO < HI");
            }
            out.push_back({name, 0, name, lo, hi, true});
            continue;
        }
        const bssrdf::Param* p = declaredParam(m, name, "--params");
        if (!seen.insert(name).second)
            throw core::Error("--params", 0, "'" + name + "' is given twice");
        if (p->type == bssrdf::ParamType::Bool)
            throw core::Error("--params", 0,
                              "'" + name +
                                  "' is a bool: only float and colour "
                                  "parameters can be fitted");
        double lo = p->min, hi = p->max;
        if (eq != std::string::npos) {
            const std::string range = spec.substr(eq + 1);
            const size_t comma = range.find(',');
            if (comma == std::string::npos)
                throw core::Error("--params", 0,
                                  "'" + spec + "': expected NAME=LO,HI for a narrower range");
            lo = parseBound(range.substr(0, comma), name + " lower bound");
            hi = parseBound(range.substr(comma + 1), name + " upper bound");
            if (lo < p->min || hi > p->max || !(lo < hi))
                throw core::Error("--params", 0,
                                  "'" + spec + "': the range must lie inside the declared [" +
                                      core::formatNumber(p->min, 6) + ", " +
                                      core::formatNumber(p->max, 6) + "] (line " +
                                      std::to_string(p->line) + ") with LO < HI");
        }
        if (!(lo < hi))
            throw core::Error("--params", 0,
                              "'" + name + "' has an empty range [" + core::formatNumber(lo, 6) +
                                  ", " + core::formatNumber(hi, 6) + "]: nothing to fit");
        if (p->type == bssrdf::ParamType::Float) {
            out.push_back({name, 0, name, lo, hi});
        } else {
            for (int c = 0; c < 3; ++c)
                out.push_back({name, c, name + "." + "rgb"[c], lo, hi});
        }
    }
    if (out.empty()) throw core::Error("--params", 0, "give at least one parameter to fit");
    return out;
}

void setParameters(const bssrdf::Model& m, const std::vector<std::string>& specs,
                   bssrdf::ParamValues& values) {
    for (const std::string& spec : specs) {
        const size_t eq = spec.find('=');
        if (eq == std::string::npos)
            throw core::Error("--set", 0, "'" + spec + "': expected NAME=VALUE");
        const std::string name = spec.substr(0, eq);
        const bssrdf::Param* p = declaredParam(m, name, "--set");
        std::vector<double> v;
        std::string rest = spec.substr(eq + 1);
        for (size_t start = 0;;) {
            const size_t comma = rest.find(',', start);
            const std::string item = rest.substr(start, comma - start);
            char* end = nullptr;
            const double x = std::strtod(item.c_str(), &end);
            if (item.empty() || *end != '\0' || !std::isfinite(x))
                throw core::Error("--set", 0, "'" + spec + "': '" + item + "' is not a number");
            v.push_back(x);
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
        const size_t want = p->type == bssrdf::ParamType::Color ? 3 : 1;
        if (v.size() == 1 && want == 3) v = {v[0], v[0], v[0]};
        if (v.size() != want)
            throw core::Error("--set", 0,
                              "'" + spec + "': " + name + " takes " +
                                  (want == 3 ? "R,G,B or one value" : "one value"));
        const double lo = p->type == bssrdf::ParamType::Bool ? 0 : p->min;
        const double hi = p->type == bssrdf::ParamType::Bool ? 1 : p->max;
        for (double x : v)
            if (x < lo || x > hi)
                throw core::Error("--set", 0,
                                  "'" + spec + "': outside the declared range [" +
                                      core::formatNumber(lo, 6) + ", " + core::formatNumber(hi, 6) +
                                      "] (" + m.path + " line " + std::to_string(p->line) + ")");
        auto& slot = values[name];
        for (size_t c = 0; c < want; ++c)
            slot[c] = float(v[c]);
    }
}

void applyFit(const std::vector<FitVariable>& vars, const std::vector<double>& x,
              bssrdf::ParamValues& values) {
    for (size_t i = 0; i < vars.size() && i < x.size(); ++i)
        if (!vars[i].medium) values[vars[i].param][size_t(vars[i].component)] = float(x[i]);
}

void applyMedium(const std::vector<FitVariable>& vars, const std::vector<double>& x,
                 const material::MaterialParams& base, material::MaterialParams& p) {
    p = base;
    for (size_t i = 0; i < vars.size() && i < x.size(); ++i) {
        if (vars[i].param == kSigmaScale) {
            p.sigmaA = base.sigmaA * x[i];
            p.sigmaS = base.sigmaS * x[i];
        } else if (vars[i].param == kMediumG) {
            p.g = x[i];
        }
    }
}

std::vector<double> modelOnTarget(const bssrdf::ModelEntry& e, const bssrdf::ParamValues& values,
                                  const FitTarget& t, std::string* problem) {
    std::vector<core::BinNodes> nodes(t.ref.size());
    std::vector<double> radii;
    for (size_t i = 0; i < t.ref.size(); ++i) {
        nodes[i] = core::areaAverageNodes(t.edges[i], t.edges[i + 1]);
        radii.insert(radii.end(), nodes[i].r.begin(), nodes[i].r.end());
    }
    const bssrdf::Profile p = bssrdf::evaluateProfile(
        e.programs.at("pencil_profile.comp").id(), *e.model, values, builtinsOf(t.params), radii);
    if (std::string bad = bssrdf::profileProblem(p); !bad.empty()) {
        if (problem) *problem = t.preset + " " + "RGB"[t.channel] + ": " + bad;
        return {};
    }
    std::vector<double> model(t.ref.size());
    for (size_t i = 0; i < t.ref.size(); ++i)
        for (size_t k = 0; k < 4; ++k)
            model[i] += nodes[i].w[k] * p.value[4 * i + k][t.channel];
    return model;
}

std::vector<double> relErrOnTargets(const bssrdf::ModelEntry& e, const bssrdf::ParamValues& values,
                                    const std::vector<FitTarget>& targets, std::string* problem,
                                    std::vector<double>* squared) {
    std::vector<double> out;
    if (squared) squared->clear();
    const GLuint program = e.programs.at("pencil_profile.comp").id();
    for (const FitTarget& t : targets) {
        if (t.thetaI > 0) { // the whole BSSRDF on the slice's bins
            const bssrdf::Builtins b = builtinsOf(t.params);
            const bool readsWo = !e.model->attrs.noWo;
            const SliceSampling n = sliceSampling(t.bins, readsWo);
            const std::vector<glm::dvec3> rgb = bssrdf::evaluateQueries(
                program, *e.model, values, b, sliceQueries(t.bins, t.thetaI, readsWo, n));
            std::vector<double> v(rgb.size());
            for (size_t i = 0; i < rgb.size(); ++i)
                v[i] = rgb[i][t.channel];
            const ModelSlice ms = modelSlice(t.bins, t.thetaI, t.params.eta, readsWo, n, v);
            bool finite = true;
            for (double x : ms.R)
                finite &= std::isfinite(x) && x >= 0;
            if (!finite) {
                if (problem)
                    *problem = t.preset + " " + "RGB"[t.channel] +
                               ": Bssrdf() is negative or not finite on the slice";
                out.push_back(std::numeric_limits<double>::quiet_NaN());
                if (squared) squared->push_back(std::numeric_limits<double>::quiet_NaN());
                continue;
            }
            const capture::ScoreRow row = scoreSlice(t.bins, t.slice, ms, t.ldMm);
            out.push_back(std::isfinite(row.relErr) ? row.relErr
                                                    : std::numeric_limits<double>::quiet_NaN());
            if (squared) squared->push_back(row.relErrSquared);
            continue;
        }
        const std::vector<double> model = modelOnTarget(e, values, t, problem);
        if (model.empty()) {
            out.push_back(std::numeric_limits<double>::quiet_NaN());
            if (squared) squared->push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        const core::RelativeError err =
            core::radialRelativeError(t.edges, t.ref, t.refSe, model, core::kRelErrFromLd * t.ldMm,
                                      core::kRelErrToLd * t.ldMm, t.refBatches);
        if (!err.valid() && problem)
            *problem = t.preset + " " + "RGB"[t.channel] + ": " + err.problem;
        out.push_back(err.valid() ? err.value : std::numeric_limits<double>::quiet_NaN());
        if (squared) squared->push_back(err.squared);
    }
    return out;
}

SearchResult searchParameters(const std::vector<FitVariable>& vars,
                              const std::vector<double>& start, const FitSettings& s,
                              const ObjectiveFn& fn,
                              const std::function<void(int, double)>& progress,
                              const std::atomic<bool>* cancel) {
    const unsigned n = unsigned(vars.size());
    std::vector<double> lo(n), hi(n), x(n);
    for (unsigned i = 0; i < n; ++i) {
        lo[i] = vars[i].lo;
        hi[i] = vars[i].hi;
        x[i] = std::clamp(start.at(i), lo[i], hi[i]);
    }
    Objective o{&vars, &fn, 0, std::numeric_limits<double>::infinity(), x, {}, &progress, cancel};
    // a coarse scan first, so that a start in the wrong valley does not decide the result: the
    // start and 8 n points of a Halton sequence over the ranges (log-spaced along a positive
    // range spanning more than a decade); BOBYQA starts from the best of them
    std::vector<double> first = x;
    objective(n, first.data(), nullptr, &o);
    const int scan = std::min(8 * int(n), s.maxEvaluations / 4);
    for (int k = 1; k <= scan && !(cancel && cancel->load()); ++k) {
        std::vector<double> p(n);
        for (unsigned i = 0; i < n; ++i) {
            const double u = halton(k, kPrimes[i % kPrimes.size()]);
            p[i] = lo[i] > 0 && hi[i] > 10 * lo[i] ? lo[i] * std::pow(hi[i] / lo[i], u)
                                                   : lo[i] + u * (hi[i] - lo[i]);
        }
        objective(n, p.data(), nullptr, &o);
    }
    // BOBYQA from the start; where the model was not finite during a run (its quadratic model
    // then holds a wall of penalties), again from the best point with a smaller first step, at
    // most kRestarts times while the budget lasts
    constexpr int kRestarts = 3;
    nlopt_result res = NLOPT_FAILURE;
    for (int run = 0; run <= kRestarts; ++run) {
        const size_t notFiniteBefore = o.notFinite;
        const int budget = s.maxEvaluations - o.evaluations;
        if (budget <= 0) break;
        nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, n);
        o.opt = opt;
        nlopt_set_lower_bounds(opt, lo.data());
        nlopt_set_upper_bounds(opt, hi.data());
        nlopt_set_min_objective(opt, objective, &o);
        nlopt_set_xtol_rel(opt, s.xtolRel);
        nlopt_set_maxeval(opt, budget);
        // the first steps (BOBYQA's trust region starts there): a tenth of each range, but at
        // most half the start's magnitude, so that a parameter spanning decades ([0.1, 50])
        // is first explored near where it starts; halved with each restart
        std::vector<double> step(n);
        for (unsigned i = 0; i < n; ++i) {
            const double range = hi[i] - lo[i], at = std::abs(o.bestX[i]);
            step[i] = std::clamp(0.5 * at, 0.01 * range, 0.1 * range) * std::ldexp(1.0, -run);
        }
        nlopt_set_initial_step(opt, step.data());
        std::vector<double> from = o.bestX;
        double fmin = 0;
        res = nlopt_optimize(opt, from.data(), &fmin);
        nlopt_destroy(opt);
        o.opt = nullptr;
        const bool walled = o.notFinite > notFiniteBefore;
        if (!walled || res == NLOPT_FORCED_STOP || res == NLOPT_MAXEVAL_REACHED) break;
    }
    if (o.evaluations >= s.maxEvaluations && res != NLOPT_FORCED_STOP) res = NLOPT_MAXEVAL_REACHED;
    SearchResult r;
    r.status = stopReason(res);
    r.converged = res == NLOPT_XTOL_REACHED || res == NLOPT_FTOL_REACHED || res == NLOPT_SUCCESS;
    r.evaluations = o.evaluations;
    r.problems = o.problems;
    r.start = x;
    r.best = o.bestX;
    r.bestObjective = o.best;
    return r;
}

double meanSquared(const std::vector<double>& squared) {
    double sum = 0;
    for (double e2 : squared)
        sum += e2;
    return squared.empty() ? std::numeric_limits<double>::quiet_NaN()
                           : sum / double(squared.size());
}

FitResult fitModel(const bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars,
                   const std::vector<FitTarget>& targets, const FitSettings& s,
                   const std::function<void(int, double)>& progress,
                   const std::atomic<bool>* cancel) {
    if (!e.usable()) throw core::Error(e.displayPath, 0, "the model is not usable");
    if (targets.empty()) throw core::Error("fit", 0, "no targets to fit to");
    std::vector<double> start;
    for (const FitVariable& v : vars)
        start.push_back(v.param == kSigmaScale ? 1.0
                        : v.param == kMediumG  ? double(targets.front().params.g)
                                               : double(e.values.at(v.param)[size_t(v.component)]));
    bssrdf::ParamValues values = e.values;
    // the targets with the medium the model is evaluated with (the references unchanged)
    std::vector<FitTarget> work = targets;
    auto set = [&](const std::vector<double>& x) {
        applyFit(vars, x, values);
        for (size_t t = 0; t < work.size(); ++t)
            applyMedium(vars, x, targets[t].params, work[t].params);
    };
    const ObjectiveFn fn = [&](const std::vector<double>& x, std::string& problem) {
        set(x);
        std::vector<double> squared;
        relErrOnTargets(e, values, work, &problem, &squared);
        return meanSquared(squared);
    };
    const SearchResult sr = searchParameters(vars, start, s, fn, progress, cancel);
    FitResult r;
    static_cast<SearchResult&>(r) = sr;
    std::vector<double> squared;
    set(r.start);
    r.relErrStart = relErrOnTargets(e, values, work, nullptr, &squared);
    r.startObjective = meanSquared(squared);
    set(r.best);
    r.relErrBest = relErrOnTargets(e, values, work);
    return r;
}

std::string withDefaults(const bssrdf::Model& m, const bssrdf::ParamValues& values,
                         const std::string& note) {
    std::vector<std::string> lines;
    std::istringstream in(m.source);
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    for (const bssrdf::Param& p : m.params) {
        auto it = values.find(p.name);
        if (it == values.end() || p.line < 1 || size_t(p.line) > lines.size()) continue;
        std::istringstream tok(lines[size_t(p.line) - 1]);
        std::vector<std::string> t;
        for (std::string w; tok >> w;)
            t.push_back(w);
        std::string out;
        if (p.type == bssrdf::ParamType::Float && t.size() >= 5)
            out = t[0] + " " + t[1] + " " + t[2] + " " + t[3] + " " +
                  core::formatNumber(it->second[0], 7);
        else if (p.type == bssrdf::ParamType::Color && t.size() >= 5)
            out = t[0] + " " + t[1] + " " + core::formatNumber(it->second[0], 7) + " " +
                  core::formatNumber(it->second[1], 7) + " " + core::formatNumber(it->second[2], 7);
        else
            continue;
        lines[size_t(p.line) - 1] = out;
    }
    std::string text;
    for (size_t i = 0; i < lines.size(); ++i) {
        text += lines[i] + "\n";
        if (i == 0) text += "# " + note + "\n";
    }
    return text;
}

} // namespace app
