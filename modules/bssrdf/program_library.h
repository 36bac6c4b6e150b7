// bssrdf model library: every materials/*.bssrdf with its last good parse, its last good GL
// program per consumer, its parameter values and its current problem. Reloading keeps the
// last good state on any error (parse, compile, link, missing function) and recovers on the
// next good save; parameter values survive when name and type persist. Each program records
// the shader files it was built from (shader::Record): a changed shader file rebuilds exactly
// the programs that read it. With a probe set (model_probe.h), a new or changed model is adopted
// only once its first evaluation finished in time elsewhere; until then the last good version
// stays in use.
#pragma once

#include "bssrdf/model_probe.h"
#include "bssrdf/program.h"

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bssrdf {

struct Problem {
    std::string file; // display path, e.g. materials/dipole.bssrdf or shaders/x.comp
    int line = 0;
    std::string message;
    std::string text() const; // "file:line: message"
};

// A version of a model that parsed and built, waiting for its check before it is adopted.
struct PendingModel {
    Model model;
    std::map<std::string, gl::Program> programs; // all consumers, or those rebuilt
    bool newModel = true;                        // false: programs rebuilt for new shader files
    std::unique_ptr<PendingProbe> probe;
    double checkStartMs = 0; // core::secondsSinceStart() when the check started, in ms
};

struct ModelEntry {
    std::filesystem::path file;
    std::string displayPath;                     // relative to the project root
    std::optional<Model> model;                  // last good parse (absent until one succeeds)
    std::map<std::string, gl::Program> programs; // consumer template -> last good program
    shader::Records shaders; // consumer template -> its shader files (not the model file)
    ParamValues values;
    std::optional<Problem> problem;        // set while the file on disk is broken
    long long generation = 0;              // bumps on every successful (re)load or program rebuild
    long long modelGeneration = 0;         // bumps when the model itself (the parse) is replaced
    std::unique_ptr<PendingModel> pending; // a newer version under its check (probe)
    // The material inverts R_dr with this model (set by its user): a new version's inversion
    // program has its code generated while the version is checked, as the pencil program's is
    // (program_library.cpp: by the check's process where it evaluates the program, else here).
    bool inversionInUse = true;
    bool checking() const { return pending != nullptr; }
    bool usable() const { return model.has_value() && programs.count("pencil_profile.comp"); }
    bool hasInversion() const { return model && model->diffuseReflectance.has_value(); }
};

class ModelLibrary {
  public:
    ModelLibrary(std::filesystem::path root, std::vector<std::string> consumers);

    // Loads every materials/*.bssrdf (sorted by name).
    void scanAll();
    // Re-reads one model file (added, changed or deleted). Returns true if anything changed.
    bool reload(const std::filesystem::path& file);
    // Reacts to a list of changed paths from the file watcher: a .bssrdf file reloads its model,
    // and so does a data file of a table model; any other file rebuilds the programs whose
    // shader::Record lists it (an entry whose last
    // load failed loads again in full). Returns true if anything changed.
    bool onFilesChanged(const std::vector<std::filesystem::path>& paths);
    // Adds a model file outside materials/ (File → Open model / CLI --model).
    ModelEntry& open(const std::filesystem::path& file);

    std::vector<ModelEntry>& entries() { return m_entries; }
    const std::vector<ModelEntry>& entries() const { return m_entries; }
    ModelEntry* find(const std::string& nameOrPath);
    const std::filesystem::path& root() const { return m_root; }
    const shader::Sources& sources() const { return m_sources; }
    // Checks every new or changed model before adopting it (model_probe.h). Off by default.
    void setProbe(ProbeStarter starter) { m_probe = std::move(starter); }
    // Adopts the models whose check passed, records a problem for those whose check failed
    // (the last good version stays). Never blocks. Returns true if anything changed.
    bool pollProbes();
    // Waits for every check under way (each bounded by its time limit), then as pollProbes().
    bool waitForProbes();
    bool checking() const;

    // Problems not tied to one model (e.g. a shader template that fails for every model).
    const std::vector<Problem>& problems() const { return m_problems; }

  private:
    void load(ModelEntry& e);
    void rebuild(ModelEntry& e, const std::vector<std::string>& consumers);
    // Checks `c` first when a probe is set, else adopts it at once.
    // Starts the check of c.model unless there is none to make or it runs already; false (and
    // the entry's problem set) when it cannot be started.
    bool startProbe(ModelEntry& e, PendingModel& c);
    void propose(ModelEntry& e, PendingModel c);
    void adopt(ModelEntry& e, PendingModel c);
    bool finishProbes(bool block);
    std::string displayPathOf(const std::filesystem::path& file) const;

    std::filesystem::path m_root;
    shader::Sources m_sources;
    std::vector<std::string> m_consumers;
    std::vector<ModelEntry> m_entries;
    std::vector<Problem> m_problems;
    ProbeStarter m_probe;
};

} // namespace bssrdf
