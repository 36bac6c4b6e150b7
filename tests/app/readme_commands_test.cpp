// Every command line the README shows — in code blocks and inline — runs and exits 0, at small
// sizes: counts and sizes are replaced by small ones (`--paths 1e6` → `--paths 20000`), the
// Slurm variable by a shard number, a glob by the files it matches, `...` by the arguments of
// the command above; sweeps are cut to a case or two (params-lab one η, compare two presets).
// Synopses (with [ ], | or parentheses) and bare names are not command lines. The README keeps its
// word: a command it shows that fails fails this test.
#include "../support/cli_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <sstream>

namespace {
namespace fs = std::filesystem;

std::vector<std::string> words(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> out;
    for (std::string w; in >> w;)
        out.push_back(w);
    return out;
}

// The README's concrete command lines, in order: code-block lines (joined over trailing
// backslashes, comments cut) and inline `...` spans that start with bssrdf-workbench.
std::vector<std::string> readmeCommands(const std::string& text) {
    std::vector<std::string> out;
    auto keep = [&](std::string cmd) {
        cmd = std::regex_replace(cmd, std::regex("\\s+"), " ");
        if (cmd.rfind("bssrdf-workbench ", 0) != 0) return;
        if (cmd.find_first_of("[]|()") != std::string::npos) return; // a synopsis
        if (cmd.find(" --") == std::string::npos && cmd.find("defaults") == std::string::npos &&
            cmd.find(" bench ") == std::string::npos)
            return; // a bare name in prose
        out.push_back(cmd);
    };
    std::istringstream in(text);
    bool fenced = false;
    std::string pending;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("```", 0) == 0) {
            fenced = !fenced;
            continue;
        }
        if (!fenced) continue;
        if (const size_t hash = line.find("  #"); hash != std::string::npos) line.resize(hash);
        const bool continued = !line.empty() && line.back() == '\\';
        if (continued) line.pop_back();
        pending += " " + line;
        if (continued) continue;
        const size_t start = pending.find_first_not_of(' ');
        keep(start == std::string::npos ? "" : pending.substr(start));
        pending.clear();
    }
    // inline spans (may run over a line break)
    const std::regex span("`(bssrdf-workbench [^`]*)`");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), span);
         it != std::sregex_iterator(); ++it)
        keep((*it)[1].str());
    return out;
}

// Small sizes for a test run.
std::vector<std::string> smallArgs(std::vector<std::string> w, const fs::path& dir) {
    const std::map<std::string, std::string> small = {{"--paths", "20000"},
                                                      {"--points", "2000"},
                                                      {"--width", "64"},
                                                      {"--height", "36"},
                                                      {"--frames", "1"},
                                                      {"--brute-frames", "1"},
                                                      {"--turk-iterations", "10"},
                                                      {"--albedos", "0.3,0.8"},
                                                      {"--g", "0"},
                                                      {"--size", "12"},
                                                      {"--reference-spp", "4"},
                                                      {"--model-spp", "4"}};
    std::vector<std::string> out;
    for (size_t i = 0; i < w.size(); ++i) {
        std::string a = std::regex_replace(w[i], std::regex("\\$\\{SLURM_ARRAY_TASK_ID\\}"), "1");
        if (i > 0 && small.count(w[i - 1])) a = small.at(w[i - 1]);
        if (a.find('*') != std::string::npos) { // a glob: the files it matches, in order
            const std::regex glob(std::regex_replace(a, std::regex("\\*"), ".*"));
            std::vector<std::string> hits;
            for (const auto& e : fs::directory_iterator(dir))
                if (std::regex_match(e.path().filename().string(), glob))
                    hits.push_back(e.path().filename().string());
            std::sort(hits.begin(), hits.end());
            out.insert(out.end(), hits.begin(), hits.end());
            continue;
        }
        out.push_back(a);
    }
    // a shard K/N gets one chunk of paths: N chunks in all
    for (size_t i = 0; i + 1 < out.size(); ++i)
        if (out[i] == "--shard")
            for (size_t j = 0; j + 1 < out.size(); ++j)
                if (out[j] == "--paths")
                    out[j + 1] = std::to_string(
                        16384ull * std::stoull(out[i + 1].substr(out[i + 1].find('/') + 1)));
    if (out.size() >= 3 && out[1] == "bench" && out[2] == "pathtrace" &&
        std::find(out.begin(), out.end(), "--seconds") == out.end())
        out.insert(out.end(), {"--seconds", "0.1"});
    // compare --geometry: small images, and of the whole suite one slab and one sphere
    if (std::find(out.begin(), out.end(), "--geometry") != out.end() && out[1] == "compare") {
        for (const auto& [flag, value] : std::vector<std::pair<std::string, std::string>>{
                 {"--size", "12"}, {"--reference-spp", "4"}, {"--model-spp", "4"}})
            if (std::find(out.begin(), out.end(), flag) == out.end())
                out.insert(out.end(), {flag, value});
        if (std::find(out.begin(), out.end(), "--shapes") == out.end())
            out.insert(out.end(), {"--shapes", "slab:t=1", "sphere:r=1"});
    }
    // params-lab: one index of refraction (the albedos are cut to two above)
    if (out.size() >= 2 && out[1] == "params-lab")
        for (size_t i = 2; i + 1 < out.size(); ++i)
            if (out[i] == "--eta") out[i + 1] = "1.3";
    // compare (not --geometry): two presets when the line scores all of them
    if (out.size() >= 2 && out[1] == "compare" &&
        std::find(out.begin(), out.end(), "--geometry") == out.end() &&
        std::find(out.begin(), out.end(), "--presets") == out.end() &&
        std::find(out.begin(), out.end(), "--mco") == out.end())
        out.insert(out.end(), {"--presets", "Marble", "Skin1"});
    // bench texture-space: one case of each method
    if (out.size() >= 3 && out[1] == "bench" && out[2] == "texture-space") {
        const std::vector<std::pair<std::string, std::string>> one = {
            {"--presets", "Marble"}, {"--scales", "10"}, {"--samples", "49"},
            {"--textures", "16"},    {"--eps", "64"},    {"--sets", "1"},
            {"--points", "2000"},    {"--width", "64"},  {"--height", "36"}};
        for (const auto& [flag, value] : one)
            if (std::find(out.begin(), out.end(), flag) == out.end())
                out.insert(out.end(), {flag, value});
    }
    return out;
}

} // namespace

TEST(ReadmeCommands, EveryCommandLineShownRuns) {
    const std::string text = clitest::readText(fs::path(BW_SOURCE_ROOT) / "README.md");
    const std::vector<std::string> commands = readmeCommands(text);
    ASSERT_GE(commands.size(), 6u) << "the README's command lines were not found";
    clitest::TempDir dir("readme");
    std::vector<std::string> previous;
    for (const std::string& cmd : commands) {
        std::vector<std::string> w = words(cmd);
        // "bssrdf-workbench slab ... --gpu": the arguments of the command above
        if (auto dots = std::find(w.begin(), w.end(), "..."); dots != w.end()) {
            ASSERT_GE(previous.size(), 2u) << cmd;
            ASSERT_EQ(previous[1], w[1]) << "'...' needs the same command above: " << cmd;
            std::vector<std::string> mine(w.begin(), dots);
            std::vector<std::string> rest(dots + 1, w.end());
            // the earlier arguments, without the options this line sets again
            for (size_t i = 2; i < previous.size(); ++i) {
                if (previous[i].rfind("--", 0) == 0 &&
                    std::find(rest.begin(), rest.end(), previous[i]) != rest.end()) {
                    if (i + 1 < previous.size() && previous[i + 1].rfind("--", 0) != 0) ++i;
                    continue;
                }
                mine.push_back(previous[i]);
            }
            mine.insert(mine.end(), rest.begin(), rest.end());
            w = mine;
        }
        previous = w;
        // an array job's geometry shard: every task of the array, so the merge below has them
        if (cmd.find("--geometry") != std::string::npos &&
            cmd.find("${SLURM_ARRAY_TASK_ID}/") != std::string::npos) {
            const size_t at = cmd.find("${SLURM_ARRAY_TASK_ID}/") + 23;
            const int n = std::stoi(cmd.substr(at));
            for (int k = 2; k <= n; ++k) {
                std::vector<std::string> task = w;
                for (std::string& a : task)
                    a = std::regex_replace(a, std::regex("\\$\\{SLURM_ARRAY_TASK_ID\\}"),
                                           std::to_string(k));
                std::vector<std::string> full = smallArgs(task, dir.path());
                full[0] = BW_EXE;
                full.insert(full.begin() + 1, {"--root", BW_SOURCE_ROOT});
                const clitest::RunResult r = clitest::runCommand(full, dir.path());
                EXPECT_EQ(r.code, 0) << "README: " << cmd << " (task " << k << ")\n" << r.output;
            }
        }
        std::vector<std::string> full = smallArgs(w, dir.path());
        full[0] = BW_EXE;
        full.insert(full.begin() + 1, {"--root", BW_SOURCE_ROOT});
        std::string shown;
        for (const auto& a : full)
            shown += a + " ";
        std::printf("README: %s\n  runs: %s\n", cmd.c_str(), shown.c_str());
        const clitest::RunResult r = clitest::runCommand(full, dir.path());
        EXPECT_EQ(r.code, 0) << "README: " << cmd << "\nran: " << shown << "\n" << r.output;
    }
}
