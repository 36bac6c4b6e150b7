// capture manifest: round trip, validation errors with file and line, input checks, report.
#include "capture/capture.h"
#include "core/core.h"
#include "temp_dir.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

namespace fs = std::filesystem;
using capture_test::TempDir;
using nlohmann::json;

namespace {

const std::string kHashA = "fnv1a64:0123456789abcdef";

capture::Manifest sampleManifest() {
    capture::Manifest m;
    m.name = "dipole_skin";
    m.createdUtc = "2024-05-01T12:00:00Z";
    m.programVersion = "0.1.0";
    m.glRenderer = "llvmpipe (LLVM 15.0.6, 256 bits)";
    m.glVersion = "4.5 (Core Profile) Mesa 22.3.6";
    m.models.push_back({"materials/dipole.bssrdf", kHashA, "builtin"});
    m.params = {{"preset", "skin1"},
                {"material", {{"sigma_a", {0.032, 0.17, 0.48}}, {"eta", 1.3}}}};
    m.settings = {{"seed", 42}, {"plot", {{"rMax_mm", 8.0}, {"samples", 200}}}};
    m.outputs.push_back({"pencil_plot", "pencil_plot.csv", "csv", 1e-7, 1e-5,
                         "float32 GPU evaluation: 64 ulp relative", kHashA});
    return m;
}

void writeText(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

int lineOf(const std::string& text, const std::string& needle) {
    size_t at = text.find(needle);
    return at == std::string::npos ? -1 : core::lineOfOffset(text, at);
}

// Writes the sample manifest's JSON after `edit`, reads it back and returns the error.
core::Error readEdited(const fs::path& dir, const std::function<void(json&)>& edit,
                       std::string* textOut = nullptr) {
    json j = capture::toJson(sampleManifest());
    edit(j);
    std::string text = j.dump(2);
    writeText(dir / "manifest.json", text);
    if (textOut) *textOut = text;
    try {
        capture::readManifest(dir);
    } catch (const core::Error& e) {
        return e;
    }
    ADD_FAILURE() << "expected an error for " << text;
    return core::Error("", 0, "");
}

} // namespace

TEST(Manifest, RoundTripWriteRead) {
    TempDir tmp;
    fs::path dir = tmp.path() / "dipole_skin";
    capture::Manifest m = sampleManifest();
    capture::writeManifest(dir, m);
    capture::Manifest back = capture::readManifest(dir);
    EXPECT_EQ(capture::toJson(back), capture::toJson(m));
    EXPECT_EQ(back.formatVersion, capture::kFormatVersion);
    EXPECT_EQ(back.name, m.name);
    ASSERT_EQ(back.outputs.size(), 1u);
    EXPECT_EQ(back.outputs[0].absTol, 1e-7); // doubles survive JSON exactly
    EXPECT_EQ(back.outputs[0].relTol, 1e-5);
    EXPECT_EQ(back.outputs[0].tolNote, m.outputs[0].tolNote);
    EXPECT_EQ(back.models[0].source, "builtin");
    EXPECT_EQ(back.params, m.params);
    EXPECT_EQ(back.settings, m.settings);

    // Stable bytes: writing the read-back manifest again gives the same file.
    std::string first = core::readFile(dir / "manifest.json");
    capture::writeManifest(dir, back);
    EXPECT_EQ(core::readFile(dir / "manifest.json"), first);
    EXPECT_EQ(first.back(), '\n');
    EXPECT_NE(first.find("\n  \"formatVersion\": 1"), std::string::npos) << first;
}

TEST(Manifest, FromJsonReportsFileWithoutLine) {
    json j = capture::toJson(sampleManifest());
    j.erase("name");
    try {
        capture::fromJson(j, "memory.json");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "memory.json");
        EXPECT_EQ(e.line(), 0);
        EXPECT_EQ(e.message(), "missing key 'name'");
    }
}

TEST(Manifest, CorruptJsonReportsFileAndLine) {
    TempDir tmp;
    writeText(tmp.path() / "manifest.json",
              "{\n  \"formatVersion\": 1,\n  \"name\": \"x\"\n  \"models\": []\n}\n");
    try {
        capture::readManifest(tmp.path());
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), (tmp.path() / "manifest.json").string());
        EXPECT_EQ(e.line(), 4);
        EXPECT_NE(e.message().find("invalid JSON"), std::string::npos) << e.what();
    }
    writeText(tmp.path() / "manifest.json", "{\n  \"formatVersion\": 1,\n");
    try {
        capture::readManifest(tmp.path());
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_GE(e.line(), 2) << e.what();
        EXPECT_NE(e.message().find("invalid JSON"), std::string::npos) << e.what();
    }
}

TEST(Manifest, MissingManifestOrFolder) {
    TempDir tmp;
    try {
        capture::readManifest(tmp.path());
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), (tmp.path() / "manifest.json").string());
        EXPECT_NE(e.message().find("missing"), std::string::npos);
    }
    try {
        capture::readManifest(tmp.path() / "nope");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(e.message().find("no capture folder"), std::string::npos) << e.what();
    }
}

TEST(Manifest, FormatVersionChecks) {
    TempDir tmp;
    std::string text;
    core::Error e = readEdited(
        tmp.path(), [](json& j) { j["formatVersion"] = 7; }, &text);
    EXPECT_EQ(e.message(), "format version 7 is newer than this program's 1");
    EXPECT_EQ(e.line(), lineOf(text, "\"formatVersion\""));
    e = readEdited(tmp.path(), [](json& j) { j["formatVersion"] = 0; });
    EXPECT_NE(e.message().find("not valid"), std::string::npos) << e.what();
    e = readEdited(tmp.path(), [](json& j) { j["formatVersion"] = "1"; });
    EXPECT_EQ(e.message(), "formatVersion: expected an integer, got string");
    e = readEdited(tmp.path(), [](json& j) { j.erase("formatVersion"); });
    EXPECT_NE(e.message().find("missing format version"), std::string::npos);
    // A newer version is reported even when the rest of the document is unknown.
    e = readEdited(tmp.path(), [](json& j) { j = {{"formatVersion", 2}, {"stuff", 1}}; });
    EXPECT_NE(e.message().find("newer"), std::string::npos);
}

TEST(Manifest, MissingAndUnknownKeys) {
    TempDir tmp;
    std::string text;
    core::Error e = readEdited(tmp.path(), [](json& j) { j.erase("outputs"); });
    EXPECT_EQ(e.message(), "missing key 'outputs'");
    e = readEdited(
        tmp.path(), [](json& j) { j["outputs"][0].erase("relTol"); }, &text);
    EXPECT_EQ(e.message(), "outputs[0]: missing key 'relTol'");
    EXPECT_EQ(e.line(), lineOf(text, "\"outputs\"") + 1); // the entry's opening brace
    e = readEdited(tmp.path(), [](json& j) { j["models"][0].erase("hash"); });
    EXPECT_EQ(e.message(), "models[0]: missing key 'hash'");
    e = readEdited(
        tmp.path(), [](json& j) { j["outputs"][0]["relTolerance"] = 1; }, &text);
    EXPECT_EQ(e.message(), "outputs[0].relTolerance: unknown key");
    EXPECT_EQ(e.line(), lineOf(text, "\"relTolerance\""));
    e = readEdited(tmp.path(), [](json& j) { j["glRendrer"] = ""; });
    EXPECT_EQ(e.message(), "glRendrer: unknown key");
    // a recorded input (exr_input) has no tolerance: neither key is accepted, and it round-trips
    e = readEdited(tmp.path(), [](json& j) { j["outputs"][0]["kind"] = "exr_input"; });
    EXPECT_EQ(e.message(), "outputs[0].absTol: unknown key");
    const fs::path dir = tmp.path() / "input";
    fs::create_directories(dir);
    capture::Manifest m = sampleManifest();
    m.outputs[0].kind = "exr_input";
    capture::writeManifest(dir, m);
    const std::string written = core::readFile(dir / capture::kManifestFileName);
    EXPECT_EQ(written.find("absTol"), std::string::npos) << written;
    EXPECT_EQ(capture::readManifest(dir).outputs[0].kind, "exr_input");
}

TEST(Manifest, WrongTypes) {
    TempDir tmp;
    std::string text;
    core::Error e = readEdited(
        tmp.path(), [](json& j) { j["name"] = 5; }, &text);
    EXPECT_EQ(e.message(), "name: expected a string, got number");
    EXPECT_EQ(e.line(), lineOf(text, "\"name\""));
    e = readEdited(
        tmp.path(), [](json& j) { j["outputs"][0]["absTol"] = "1e-5"; }, &text);
    EXPECT_EQ(e.message(), "outputs[0].absTol: expected a number, got string");
    EXPECT_EQ(e.line(), lineOf(text, "\"absTol\""));
    e = readEdited(tmp.path(), [](json& j) { j["params"] = json::array(); });
    EXPECT_EQ(e.message(), "params: expected an object, got array");
    e = readEdited(tmp.path(), [](json& j) { j["models"] = json::object(); });
    EXPECT_EQ(e.message(), "models: expected an array, got object");
    e = readEdited(tmp.path(), [](json& j) { j["outputs"][0] = 3; });
    EXPECT_EQ(e.message(), "outputs[0]: expected an object, got number");
    e = readEdited(tmp.path(), [](json& j) { j = json::array(); });
    EXPECT_EQ(e.message(), "expected a JSON object, got array");
}

TEST(Manifest, InvalidValues) {
    TempDir tmp;
    core::Error e = readEdited(tmp.path(), [](json& j) { j["outputs"][0]["relTol"] = -1e-5; });
    EXPECT_EQ(e.message(), "outputs[0].relTol: must be finite and >= 0");
    e = readEdited(tmp.path(), [](json& j) { j["outputs"][0]["kind"] = "png"; });
    EXPECT_EQ(e.message(),
              "outputs[0].kind: unknown output kind 'png' (known: csv, csv_stat, exr_stat, exr, "
              "exr_input)");
    e = readEdited(tmp.path(), [](json& j) { j["outputs"][0]["hash"] = "abc"; });
    EXPECT_NE(e.message().find("not a content hash"), std::string::npos);
    e = readEdited(tmp.path(), [](json& j) { j["name"] = "my capture"; });
    EXPECT_NE(e.message().find("not a valid capture name"), std::string::npos);
    e = readEdited(tmp.path(), [](json& j) { j["outputs"] = json::array(); });
    EXPECT_NE(e.message().find("at least one"), std::string::npos);
    e = readEdited(tmp.path(), [](json& j) {
        j["outputs"].push_back(j["outputs"][0]);
        j["outputs"][1]["file"] = "other.csv";
    });
    EXPECT_EQ(e.message(), "outputs[1].stage: stage 'pencil_plot' is listed twice");
    e = readEdited(tmp.path(), [](json& j) { j["outputs"][0]["file"] = "manifest.json"; });
    EXPECT_NE(e.message().find("manifest itself"), std::string::npos);
}

TEST(Manifest, PathsMustStayInsideTheirFolder) {
    TempDir tmp;
    for (std::string bad : {"../x.csv", "/etc/passwd", "a/../../x.csv", "..", "a//b.csv",
                            "C:/x.csv", "a\\b.csv", ""}) {
        core::Error e = readEdited(tmp.path(), [&](json& j) { j["outputs"][0]["file"] = bad; });
        EXPECT_EQ(e.message().rfind("outputs[0].file: '" + bad + "': ", 0), 0u) << e.what();
    }
    core::Error e =
        readEdited(tmp.path(), [](json& j) { j["models"][0]["path"] = "../outside.bssrdf"; });
    EXPECT_NE(e.message().find("escape"), std::string::npos) << e.what();
    EXPECT_EQ(capture::relativePathProblem("materials/dipole.bssrdf"), "");
    EXPECT_EQ(capture::relativePathProblem("sub/dir/a.csv"), "");
    EXPECT_NE(capture::relativePathProblem("/abs"), "");

    // writeManifest refuses to write what readManifest would reject.
    capture::Manifest m = sampleManifest();
    m.outputs[0].file = "../escape.csv";
    EXPECT_THROW(capture::writeManifest(tmp.path() / "w", m), core::Error);
    EXPECT_FALSE(fs::exists(tmp.path() / "w" / "manifest.json"));
}

TEST(Manifest, UnwritablePathThrowsNamingIt) {
    TempDir tmp;
    writeText(tmp.path() / "plain_file", "x");
    fs::path dir = tmp.path() / "plain_file" / "cap";
    try {
        capture::writeManifest(dir, sampleManifest());
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find((tmp.path() / "plain_file").string()),
                  std::string::npos)
            << e.what();
    }
}

TEST(Manifest, NamesHashesAndTime) {
    EXPECT_TRUE(capture::isValidName("dipole_skin-2.v1"));
    EXPECT_FALSE(capture::isValidName(""));
    EXPECT_FALSE(capture::isValidName(".."));
    EXPECT_FALSE(capture::isValidName("a/b"));
    EXPECT_FALSE(capture::isValidName(".hidden")); // a hidden folder the Captures panel skips
    EXPECT_FALSE(capture::isValidName("-x"));      // an option to the command line
    EXPECT_EQ(capture::nameProblem("my capture"), "letters, digits, '_', '-' and '.' only");
    EXPECT_TRUE(capture::isHash(core::hashHex("abc")));
    EXPECT_FALSE(capture::isHash("fnv1a64:0123456789ABCDEF"));
    std::string now = capture::utcNow();
    ASSERT_EQ(now.size(), 20u) << now;
    EXPECT_EQ(now[10], 'T');
    EXPECT_EQ(now.back(), 'Z');
}

TEST(Manifest, HashFile) {
    TempDir tmp;
    writeText(tmp.path() / "a.txt", "hello");
    EXPECT_EQ(capture::hashFile(tmp.path() / "a.txt"), core::hashHex("hello"));
    try {
        capture::hashFile(tmp.path() / "missing.txt");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), (tmp.path() / "missing.txt").string());
    }
}

TEST(Manifest, CheckInputs) {
    TempDir tmp;
    fs::path root = tmp.path() / "project";
    fs::path dir = root / "captures" / "dipole_skin";
    fs::create_directories(root / "materials");
    writeText(root / "materials" / "dipole.bssrdf", "model v1");
    capture::Manifest m = sampleManifest();
    m.models[0].hash = capture::hashFile(root / "materials" / "dipole.bssrdf");
    capture::Table t{{}, {"r_mm", "R"}, {{0.5, 0.25}}};
    m.outputs[0] = capture::writeCsvStage(dir, "pencil_plot", "pencil_plot.csv", t, 0, 1e-6,
                                          "exact CPU double");
    capture::writeManifest(dir, m);
    EXPECT_TRUE(capture::checkInputs(m, dir, root).empty());

    writeText(root / "materials" / "dipole.bssrdf", "model v2");
    auto problems = capture::checkInputs(m, dir, root);
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_EQ(problems[0], "materials/dipole.bssrdf: content hash changed (recorded " +
                               m.models[0].hash + ", now " + core::hashHex("model v2") + ")");

    fs::remove(root / "materials" / "dipole.bssrdf");
    fs::remove(dir / "pencil_plot.csv");
    problems = capture::checkInputs(m, dir, root);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_EQ(problems[0], "materials/dipole.bssrdf: missing");
    EXPECT_EQ(problems[1], "pencil_plot.csv: output of stage pencil_plot missing from the capture");

    writeText(dir / "pencil_plot.csv", "r_mm,R\n0.5,0.3\n");
    problems = capture::checkInputs(m, dir, root);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_NE(problems[1].find("pencil_plot.csv: content hash changed since recording"),
              std::string::npos);
}

TEST(Manifest, ReplayReport) {
    capture::ReplayReport report;
    EXPECT_FALSE(report.pass()); // nothing compared is not a pass
    capture::Table t{{}, {"x"}, {{1.0}}};
    report.stages.push_back(capture::compareTables("a", t, t, 0, 0));
    EXPECT_TRUE(report.pass());
    EXPECT_EQ(report.text(), "PASS a  1 value, exact match\nreplay PASS: 1 stage\n");
    report.inputProblems.push_back("materials/x.bssrdf: missing");
    EXPECT_FALSE(report.pass());
    capture::Table u{{}, {"x"}, {{2.0}}};
    report.stages.push_back(capture::compareTables("b", t, u, 0, 0.1));
    std::string text = report.text();
    EXPECT_EQ(text.rfind("INPUT materials/x.bssrdf: missing\n", 0), 0u) << text;
    EXPECT_NE(text.find("\nFAIL b  "), std::string::npos) << text;
    EXPECT_NE(text.find("replay FAIL: 1 of 2 stages failed, 1 input problem\n"), std::string::npos)
        << text;
}

namespace {
std::string swap(std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}
} // namespace

// modelTokens: comments and whitespace go, code and preprocessor lines inside sections stay.
TEST(ModelTokens, CommentsAndWhitespaceOnly) {
    const std::string a = "analytic radial\n# header comment\n::begin initializer\n"
                          "#define K 2.0\nfloat f() { return K; } // why\n::end initializer\n";
    const std::string b = "analytic   radial\n\n# another comment\n# more\n::begin initializer\n"
                          "#define K 2.0\n/* block\n comment */float f() {\n  return K;\n}\n"
                          "::end initializer\n";
    EXPECT_EQ(capture::modelTokens(a), capture::modelTokens(b));
    EXPECT_NE(capture::modelTokens(a), capture::modelTokens(swap(a, "2.0", "3.0")));
    // a '#' line inside a section is GLSL (a directive), not a comment
    EXPECT_NE(capture::modelTokens(a), capture::modelTokens(swap(a, "#define K 2.0\n", "")));
    // tokens stay apart: "a b" is not "ab"
    EXPECT_NE(capture::modelTokens("::begin x\nfloat a;\n::end x"),
              capture::modelTokens("::begin x\nfloata;\n::end x"));
}
