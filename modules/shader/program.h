// shader programs: builds GL programs from shader files through assemble() (assembly.h), maps
// driver errors back to file:line (diagnostics.h), and records for each program the files it
// was built from, so that hot reload rebuilds exactly the programs whose files changed.
//   Sources: where the files are. Display paths ("shaders/x.comp", "materials/m.bssrdf") are
//   relative to a root; `#include "common/y.glsl"` is resolved in the templates' folder.
//   Record: the files one program's last build attempt read or tried to read (a missing
//   include is listed too, so creating it rebuilds the program) and its successful builds.
#pragma once

#include "gl/gl.h"
#include "shader/assembly.h"

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace shader {

// Absolute, lexically normal files; the same spelling for the same file from any caller.
class Dependencies {
  public:
    void add(const std::filesystem::path& file);
    bool contains(const std::filesystem::path& file) const;
    bool containsAny(const std::vector<std::filesystem::path>& files) const;
    const std::vector<std::filesystem::path>& files() const { return m_files; }

  private:
    std::vector<std::filesystem::path> m_files;
};

// What hot reload knows of one program.
struct Record {
    Dependencies dependencies; // of the last build attempt, successful or not
    long long builds = 0;      // successful builds
};
// Programs by name (e.g. "octree_render.comp").
using Records = std::map<std::string, Record>;

// What a hot reload did: programs rebuilt, and the first failure (the failed program keeps
// its last good version), "file:line: message".
struct Reloaded {
    int rebuilt = 0;
    std::string problem;
};

class Sources {
  public:
    Sources() = default;
    // Templates in root/dir, display paths relative to root.
    explicit Sources(std::filesystem::path root, std::string dir = "shaders");
    // `dir` holds the templates; display paths start with its name ("shaders/x.comp").
    static Sources forFolder(const std::filesystem::path& dir);
    // The folder of `file` holds the templates.
    static Sources forFile(const std::filesystem::path& file) {
        return forFolder(file.parent_path());
    }

    const std::filesystem::path& root() const { return m_root; }
    std::string displayPath(const std::string& templateName) const; // "shaders/x.comp"
    std::filesystem::path fileOf(const std::string& displayPath) const;
    // Reads a file by display path; throws core::Error(displayPath, 0, why).
    std::string read(const std::string& displayPath) const;
    // Assembles the template `name` with its includes; every file read or tried goes into
    // `deps`, also when assembly throws.
    AssembledShader assemble(const std::string& name, Dependencies& deps,
                             const Extension& extension = {}) const;

  private:
    std::filesystem::path m_root;
    std::string m_dir;
};

struct StageSource {
    GLenum type; // GL_COMPUTE_SHADER, GL_VERTEX_SHADER, ...
    AssembledShader source;
};

// Compiles and links. On failure throws core::Error naming the file and line of the first
// driver error, with every diagnostic in the message; a log with no location (a link error, a
// driver format not understood) blames `blame` (default: the first stage's template) with
// "link failed: " or "compile failed: " and the raw log.
gl::Program link(const std::vector<StageSource>& stages, const std::string& blame = {});

// Assembles each (stage type, template name) from `src`, links, and updates `record`
// (dependencies of this attempt; builds counted on success). Throws like assemble() / link().
gl::Program build(const Sources& src, const std::vector<std::pair<GLenum, std::string>>& stages,
                  Record& record, const Extension& extension = {}, const std::string& blame = {});

} // namespace shader
