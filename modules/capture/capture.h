// capture: reproducible records of the workbench's state, replayed headless by tests.
//
// A capture is a folder `captures/NAME/` holding `manifest.json` plus one output file per
// recorded stage (e.g. `pencil_plot.csv`). The manifest lists the inputs (model files with
// their content hashes, every parameter and setting) and, per stage, the output file, its
// kind and the tolerance it is compared with on replay. Format version 1 is documented key
// by key in captures/README.md; this module is the only code that reads or writes it.
//
// This module is data + comparison only (no GL): the app fills in the inputs and computes the
// stages; here are the manifest's JSON form with validation, CSV tables, the per-value
// tolerance test and the replay report.
//
// Tolerance (per stage): a value passes when |actual - expected| <= absTol + relTol*|expected|.
// NaN equals NaN; equal infinities are equal; anything else involving NaN/inf fails.
// Content hashes are FNV-1a 64 (core::hashHex): "fnv1a64:" + 16 lowercase hex digits.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace capture {

constexpr int kFormatVersion = 1;
constexpr const char* kManifestFileName = "manifest.json";

// ---- manifest -------------------------------------------------------------------------------
struct ModelFile {
    std::string path;   // relative to the project root, e.g. "materials/dipole.bssrdf"
    std::string hash;   // content hash of the file when recorded
    std::string source; // the model file's full text when recorded (for diffs and forensics)
};

struct StageOutput {
    std::string stage;             // e.g. "pencil_plot"; unique within a capture
    std::string file;              // relative to the capture folder, e.g. "pencil_plot.csv"
    std::string kind = "csv";      // one of knownOutputKinds()
    double absTol = 0, relTol = 0; // csv: value passes if |a-b| <= absTol + relTol*|b|
    std::string tolNote;           // why this tolerance ("float32 GPU evaluation: 64 ulp rel")
    std::string hash;              // content hash of the file when recorded
    double alpha = 0; // csv_stat: family-wise false-alarm probability of the z-test (0, 1)
};

struct Manifest {
    int formatVersion = kFormatVersion;
    std::string name;           // folder name: letters, digits, '_', '-', '.'
    std::string createdUtc;     // ISO 8601, e.g. "2024-05-01T12:00:00Z" (see utcNow())
    std::string programVersion; // e.g. "0.1.0"
    std::string glRenderer;     // GL_RENDERER when recorded; "" when no GL was used
    std::string glVersion;      // GL_VERSION when recorded; "" when no GL was used
    std::vector<ModelFile> models;
    nlohmann::json params = nlohmann::json::object();   // all parameter values
    nlohmann::json settings = nlohmann::json::object(); // plot settings, seeds, etc.
    std::vector<StageOutput> outputs;                   // at least one
};

// Reads and validates `captureDir/manifest.json`. Throws core::Error("<dir>/manifest.json",
// line, msg) for: missing file, corrupt JSON (line of the parse error), missing / too new
// format version, missing or unknown keys, wrong types, invalid names or hashes, negative
// tolerances, duplicate stages/files, paths escaping their folder (".." or absolute).
// Errors about a key carry the line of that key's value (or of the enclosing object).
Manifest readManifest(const std::filesystem::path& captureDir);
// Validates (same rules as reading), creates the folder if needed and writes pretty JSON
// with sorted keys (stable diffs). Throws core::Error naming the path on failure.
void writeManifest(const std::filesystem::path& captureDir, const Manifest& manifest);

// A record request: a manifest of the inputs only (no outputs yet), read and written with the
// same checks otherwise (a process records it: app/captures/capture_io.h, writeRecordRequest).
Manifest readInputs(const std::filesystem::path& file);
void writeInputs(const std::filesystem::path& file, const Manifest& manifest);

nlohmann::json toJson(const Manifest& manifest);
// Validates like readManifest; errors name `fileForErrors` with line 0.
Manifest fromJson(const nlohmann::json& json, const std::string& fileForErrors);

// "exr": a deterministic image (GPU render) compared per pixel and channel with absTol/relTol.
// "exr_input": an image a stage made when recording that a replay gives back to it as an input
// instead of making it again (the scene's G-buffer: another rasteriser's sub-pixel placement must
// not move what is traced from it); not compared with this run's, its hash must match; no
// tolerance keys.
std::vector<std::string> knownOutputKinds(); // {"csv", "csv_stat", "exr_stat", "exr", "exr_input"}
bool isInputKind(std::string_view kind);
// Kinds compared by z-test at `alpha` (csv_stat; exr_stat: images with a variance per pixel,
// read and converted to tables by the app, which owns the image format).
bool isStatisticalKind(std::string_view kind);
// A capture's or a stage's name: "" when valid, else why not. [A-Za-z0-9_.-], starting with a
// letter, a digit or '_' (a leading '.' hides the folder, and "." and ".." are not folders of
// their own; a leading '-' reads as an option on the command line).
std::string nameProblem(std::string_view name);
bool isValidName(std::string_view name); // nameProblem(name) is ""
bool isHash(std::string_view text);      // "fnv1a64:" + 16 lowercase hex digits
// "" when `path` is a plain relative path that stays inside its folder, else the reason.
std::string relativePathProblem(std::string_view path);

// Untrusted captures (confine.cpp). A capture may come from someone else, so what its manifest
// names is confined: "" when the output `file` of the capture in `captureDir` resolves (symlinks
// followed) to a place inside that folder and is not itself a symlink, else the reason.
std::string outputPathProblem(const std::filesystem::path& captureDir, const std::string& file);
// "" when the input file `path` (absolute, or relative to `projectRoot` as the workbench resolves
// settings paths) resolves, symlinks followed, inside one of `folders`, else the reason naming
// them. An empty `path` (no file) is fine.
std::string confinedInputProblem(const std::string& path, const std::filesystem::path& projectRoot,
                                 const std::vector<std::filesystem::path>& folders);
std::string utcNow(); // current time as "YYYY-MM-DDTHH:MM:SSZ"

// ---- CSV tables -----------------------------------------------------------------------------
// Text form: optional '#' comment lines, one header row of column names, then one row of
// comma-separated numbers per line. Numbers are written in the shortest form that reads back
// bit-exactly (std::to_chars), "nan"/"inf"/"-inf" for non-finite values.
struct Table {
    std::vector<std::string> comments; // text after "# " (one leading space is dropped)
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows; // each row has columns.size() values

    int columnIndex(std::string_view name) const; // -1 when absent
};

// Throws core::Error(path, line, msg): missing file, no header row, empty or duplicate
// column names, ragged rows, values that are not numbers, blank lines between rows.
Table readCsv(const std::filesystem::path& path);
Table parseCsv(std::string_view text, const std::string& fileForErrors);
// Throws core::Error(path, 0, msg) when the table is malformed (no columns, ragged rows,
// names containing ',' or line breaks, comments containing line breaks) or the file cannot
// be written.
void writeCsv(const std::filesystem::path& path, const Table& table);
std::string formatCsv(const Table& table); // throws core::Error("", 0, msg) when malformed

// ---- comparison -----------------------------------------------------------------------------
struct Comparison {
    bool pass = false;
    std::string stage;
    double absTol = 0, relTol = 0;
    size_t values = 0;      // values compared
    size_t failing = 0;     // values out of tolerance
    double worstAbs = 0;    // max |a-b| over finite pairs
    double worstRel = 0;    // max |a-b|/|b| over finite pairs (inf when b == 0 != a)
    double worstExcess = 0; // max |a-b| / (absTol + relTol*|b|); > 1 means out of tolerance
    // At the value with the worst excess (valid when `where` is non-empty):
    std::string where; // e.g. "row 37 (r_mm=1.23), column G"; rows count from 1
    double expected = 0, actual = 0, diff = 0, limit = 0;
    std::string message;          // why it failed without a value location (shape, names, file)
    bool statistical = false;     // csv_stat: worstExcess = max|z| / zLimit, limit = zLimit
    std::string artifacts;        // where images of a failure were written (printed after it)
    double alpha = 0;             // csv_stat: family-wise false-alarm probability
    std::string conditioningNote; // what the per-value tolerances were (empty: none)
};

// `keyColumn` (optional) names a column whose expected value is shown in `where`.
// `conditioning` (optional): one more absolute tolerance per value, a table of the same shape as
// `actual` (a value passes when |a − b| <= absTol + relTol·|b| + conditioning), made by the
// replaying program: how far the value may lie apart on two drivers (bssrdf/conditioning.h), with
// `conditioningNote` saying so in the report.
Comparison compareTables(const std::string& stage, const Table& expected, const Table& actual,
                         double absTol, double relTol, const std::string& keyColumn = "",
                         const Table* conditioning = nullptr,
                         const std::string& conditioningNote = "");
// One line, e.g.
//   "PASS pencil_plot  600 values, worst diff 3.1e-07 (limit 1e-05, 3.1% of tolerance) at row
//    12 (r_mm=0.5), column R"
//   "FAIL pencil_plot  row count differs: expected 200, got 199"
std::string formatComparison(const Comparison& comparison);

// Monte Carlo tables (kind "csv_stat"): every column X that has a companion column
// "X_stderr" holds estimates with standard errors. Each such value pair is compared by
// z = |a − b| / sqrt(se_a² + se_b²) against the two-sided Bonferroni limit
// z_lim = Φ⁻¹(1 − alpha / (2m)) over the m compared values (so all of them pass together with
// probability ≥ 1 − alpha when both runs estimate the same means). Identical values (same
// build, same seed) give z = 0. Columns without a companion (e.g. r_mm) and values whose
// standard errors are both 0 must match exactly.
Comparison compareStatTables(const std::string& stage, const Table& expected, const Table& actual,
                             double alpha, const std::string& keyColumn = "");

// ---- recording and replay -------------------------------------------------------------------
// core::hashHex of the file's bytes; throws core::Error naming the path when unreadable.
std::string hashFile(const std::filesystem::path& path);

// Writes `table` as `captureDir/file` and returns the StageOutput describing it (hash filled).
StageOutput writeCsvStage(const std::filesystem::path& captureDir, const std::string& stage,
                          const std::string& file, const Table& table, double absTol, double relTol,
                          const std::string& tolNote);
// As writeCsvStage for a "csv_stat" output compared with compareStatTables at `alpha`.
StageOutput writeCsvStatStage(const std::filesystem::path& captureDir, const std::string& stage,
                              const std::string& file, const Table& table, double alpha,
                              const std::string& tolNote);
// Describes a file the caller wrote itself (e.g. an EXR image): validates the names and alpha
// (statistical kinds) and fills in the content hash.
StageOutput describeFileStage(const std::filesystem::path& captureDir, const std::string& stage,
                              const std::string& file, const std::string& kind, double alpha,
                              const std::string& tolNote);
// Reads the recorded CSV of `output` from `captureDir` and compares `actual` against it with
// the recorded tolerance (plus `conditioning` per value: compareTables). An unreadable recorded
// file gives a failing Comparison (message).
Comparison compareCsvStage(const StageOutput& output, const std::filesystem::path& captureDir,
                           const Table& actual, const std::string& keyColumn = "",
                           const Table* conditioning = nullptr,
                           const std::string& conditioningNote = "");

// Checks the manifest's recorded inputs against the files now on disk:
//   model missing            -> "materials/x.bssrdf: missing"
//   model content changed    -> "materials/x.bssrdf: content hash changed (recorded
//                                fnv1a64:..., now fnv1a64:...)"
//   output missing           -> "pencil_plot.csv: output of stage pencil_plot missing from
//                                the capture"
//   output edited            -> "pencil_plot.csv: content hash changed since recording ..."
// Model paths are relative to `projectRoot`, output files to `captureDir`. Empty = all good.
// A model whose text changed only in comments or whitespace compiles to the same program: it
// is a note ("materials/x.bssrdf: only comments or whitespace changed ..."), appended to
// `notes` when given, not a problem.
std::vector<std::string> checkInputs(const Manifest& manifest,
                                     const std::filesystem::path& captureDir,
                                     const std::filesystem::path& projectRoot,
                                     std::vector<std::string>* notes = nullptr);

// What a .bssrdf model compiles from: its text without comments ('#' lines outside the
// ::begin/::end sections, // and /* */ inside them) and with every run of whitespace made one
// space. Two texts with the same tokens assemble to the same GLSL apart from #line numbers.
std::string modelTokens(std::string_view text);

struct ReplayReport {
    std::vector<Comparison> stages;
    std::vector<std::string> inputProblems;
    std::vector<std::string> inputNotes; // printed as NOTE lines; they do not fail the replay
    // No input problems, at least one stage compared, every stage passed.
    bool pass() const;
    // One line per input problem ("INPUT ..."), one per stage (formatComparison), then a
    // summary line "replay PASS: 3 stages" / "replay FAIL: 1 of 3 stages failed, ...".
    std::string text() const;
};

} // namespace capture
