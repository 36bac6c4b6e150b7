// The live scoreboard (scoreboard_stage.h).
#include "pipeline/scoreboard_stage.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pipeline/param_json.h"
#include "pipeline/scoring.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace app {

bool ScoreboardStage::updateMcml(const ScoreboardInputs& in) {
    if (!in.mcml || !in.mcmlMedium) {
        const bool changed = !m_mcmlRows.empty() || !m_mcmlProblems.empty();
        m_mcmlRows.clear();
        m_mcmlProblems.clear();
        m_mcmlKey.clear();
        m_mcmlName.clear();
        return changed;
    }
    const pathtrace::Medium& m = *in.mcmlMedium;
    std::string key = in.mcmlName + core::keyOf(m) + std::to_string(in.mcml->paths) + "|" +
                      std::to_string(in.mcml->totalRd);
    for (const bssrdf::ModelEntry& e : in.library->entries())
        if (e.usable())
            key += e.displayPath + std::to_string(e.generation) + toJson(e.values).dump();
    if (key == m_mcmlKey) return false;
    m_mcmlKey = key;
    m_mcmlName = in.mcmlName;
    m_mcmlRows.clear();
    m_mcmlProblems.clear();
    // the run's medium in every channel, as `compare --mco` (cli/compare_command.cpp)
    MaterialSettings s;
    s.preset.clear();
    s.params.sigmaA = glm::dvec3(m.sigmaA);
    s.params.sigmaS = glm::dvec3(m.sigmaS);
    s.params.g = m.g;
    s.params.eta = m.eta;
    const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
    const pathtrace::SlabResult& r = *in.mcml;
    const std::vector<double> edges = binEdges(r.rMid);
    std::vector<ScoreboardRow> rows;
    for (const bssrdf::ModelEntry& e : in.library->entries()) {
        if (!e.usable()) continue;
        try {
            const bssrdf::Builtins b = builtinsOf(effectiveParams(e, s));
            const GLuint program = e.programs.at("pencil_profile.comp").id();
            std::string bad;
            const bssrdf::Profile prof = binAverageProfile(program, e, b, edges, bad);
            if (!bad.empty()) {
                m_mcmlProblems.push_back(e.displayPath + ": " + m_mcmlName + ": " + bad);
                continue;
            }
            ScoreboardRow row;
            row.score = scoreAgainstReference(edges, r.rd, r.rdStderr, r.specular, r.totalRd,
                                              r.totalRdStderr, ld, channelOf(prof, 0),
                                              modelTotalRd(program, e, b, ld, 0));
            std::string stem = e.displayPath.substr(e.displayPath.rfind('/') + 1);
            row.score.model = stem.substr(0, stem.rfind('.'));
            row.score.preset = m_mcmlName;
            row.score.channel = "R";
            row.displayPath = e.displayPath;
            rows.push_back(row);
        } catch (const std::exception& err) {
            m_mcmlProblems.push_back(e.displayPath + ": " + m_mcmlName + ": " + err.what());
        }
    }
    std::vector<capture::ScoreRow> scores;
    for (const ScoreboardRow& row : rows)
        scores.push_back(row.score);
    rankRows(scores);
    for (const capture::ScoreRow& sc : scores)
        for (const ScoreboardRow& row : rows)
            if (row.score.model == sc.model) {
                m_mcmlRows.push_back(row);
                m_mcmlRows.back().score = sc;
                break;
            }
    return true;
}

bool ScoreboardStage::update(const ScoreboardInputs& in) {
    if (!in.enabled || !in.library || !in.views || !in.reference) return false;
    const bool mcmlChanged = updateMcml(in);
    return updateReference(in) || mcmlChanged;
}

bool ScoreboardStage::updateReference(const ScoreboardInputs& in) {
    if (!in.params) {
        const bool changed = !m_rows.empty() || m_key != "none";
        m_rows.clear();
        m_notes = {"no usable model: no reference"};
        m_key = "none";
        return changed;
    }
    const ReferenceSnapshot& ref = *in.reference;
    // what the table depends on: every usable model (generation, values, σ) and the reference
    std::string key = in.referenceModel + core::keyOf(*in.params) + "|" +
                      std::to_string(ref.pathsDone) + "|" +
                      std::to_string(ref.channel[0].rMid.size()) + "|" + ref.energy;
    for (const bssrdf::ModelEntry& e : in.library->entries()) {
        auto v = in.views->find(e.displayPath);
        if (!e.usable() || v == in.views->end() || !v->second.effective) continue;
        key += e.displayPath + std::to_string(e.generation) + toJson(e.values).dump() +
               core::keyOf(builtinsOf(*v->second.effective));
    }
    if (key == m_key) return false;
    const double now = core::secondsSinceStart();
    if (ref.running && now - m_lastScored < kRescoreSeconds) return false; // later, not per frame
    m_key = key;
    m_lastScored = now;
    core::Stopwatch clock;
    m_rows.clear();
    m_notes.clear();
    m_problems.clear();
    m_paths = ref.pathsDone;
    if (ref.pathsDone == 0 || ref.channel[0].rMid.empty()) {
        m_notes.push_back("the reference has no paths yet");
        return true;
    }
    std::vector<capture::ScoreRow> scores;
    std::vector<ScoreboardRow> rows;
    std::map<std::string, double> totals;            // the ones used now (the rest are dropped)
    std::map<std::string, bssrdf::Profile> averages; // per model: its bin averages, all channels
    for (int c = 0; c < 3; ++c) {
        const pathtrace::SlabResult& r = ref.channel[size_t(c)];
        const pathtrace::Medium m = mediaOf(*in.params)[size_t(c)];
        const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
        const char* ch = c == 0 ? "R" : c == 1 ? "G" : "B";
        if (!(std::isfinite(ld) && ld > 0)) {
            m_notes.push_back(std::string(ch) + ": sigma_a = 0, no l_d to score over");
            continue;
        }
        if (r.rMid.size() < 2 || r.rMid.front() > 0.1 * ld) {
            m_notes.push_back(std::string(ch) + ": the reference's bins are too coarse for l_d = " +
                              core::formatNumber(ld, 3) + " mm (narrow the plot range)");
            continue;
        }
        const std::vector<double> edges = binEdges(r.rMid);
        const double covered = edges.back() / ld;
        for (const bssrdf::ModelEntry& e : in.library->entries()) {
            auto v = in.views->find(e.displayPath);
            if (!e.usable() || v == in.views->end() || !v->second.effective) continue;
            try {
                const bssrdf::Builtins b = builtinsOf(*v->second.effective);
                const GLuint program = e.programs.at("pencil_profile.comp").id();
                auto avg = averages.find(e.displayPath);
                if (avg == averages.end()) {
                    std::string bad;
                    bssrdf::Profile prof = binAverageProfile(program, e, b, edges, bad);
                    if (!bad.empty()) m_problems.push_back(e.displayPath + ": " + bad);
                    avg = averages
                              .emplace(e.displayPath,
                                       bad.empty() ? std::move(prof) : bssrdf::Profile{})
                              .first;
                }
                if (avg->second.value.empty()) continue; // NaN, Inf or negative: listed once
                const std::vector<double> mv = channelOf(avg->second, c);
                ScoreboardRow row;
                const std::string totalKey = e.displayPath + std::to_string(e.generation) +
                                             toJson(e.values).dump() + core::keyOf(b, ld, c);
                auto cached = m_totals.find(totalKey);
                const double total =
                    cached != m_totals.end() ? cached->second : modelTotalRd(program, e, b, ld, c);
                totals[totalKey] = total;
                row.score = scoreAgainstReference(edges, r.rd, r.rdStderr, r.specular, r.totalRd,
                                                  r.totalRdStderr, ld, mv, total, r.rdBatches);
                std::string stem = e.displayPath.substr(e.displayPath.rfind('/') + 1);
                row.score.model = stem.substr(0, stem.rfind('.'));
                row.score.preset = "current";
                row.score.channel = ch;
                row.displayPath = e.displayPath;
                row.channel = c;
                row.coveredLd = std::min(4.0, covered);
                rows.push_back(row);
            } catch (const std::exception& err) {
                // once per model (the other channels skip it), named once: a model's own error
                // (core::Error at its file and line) already starts with its path
                averages.try_emplace(e.displayPath);
                const std::string what = err.what();
                std::string problem =
                    what.rfind(e.displayPath, 0) == 0 ? what : e.displayPath + ": " + what;
                if (std::find(m_problems.begin(), m_problems.end(), problem) == m_problems.end())
                    m_problems.push_back(std::move(problem));
            }
        }
    }
    m_totals = std::move(totals);
    // rank as `compare` does, then keep each row's model and channel with its score
    for (const ScoreboardRow& r : rows)
        scores.push_back(r.score);
    rankRows(scores);
    for (const capture::ScoreRow& s : scores)
        for (const ScoreboardRow& r : rows)
            if (r.score.model == s.model && r.score.channel == s.channel) {
                ScoreboardRow out = r;
                out.score = s;
                m_rows.push_back(out);
                break;
            }
    gl::recordTiming("scoreboard", clock.ms());
    return true;
}

StageStatus ScoreboardStage::status() const {
    StageStatus st;
    st.problems = m_problems;
    st.problems.insert(st.problems.end(), m_mcmlProblems.begin(), m_mcmlProblems.end());
    st.stats.emplace_back("rows", std::to_string(m_rows.size()));
    return st;
}

} // namespace app
