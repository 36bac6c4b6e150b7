// capture manifest: symmetric toJson/fromJson with strict validation, file reading/writing.
#include "capture.h"

#include "core/core.h"
#include "detail/json_locate.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <initializer_list>
#include <set>

namespace capture {

namespace {

using detail::JsonPath;
using detail::JsonStep;
using nlohmann::json;

JsonPath child(JsonPath path, std::string key) {
    path.push_back(JsonStep{std::move(key), 0, false});
    return path;
}
JsonPath child(JsonPath path, size_t index) {
    path.push_back(JsonStep{"", index, true});
    return path;
}

// Validating reader over a parsed document; `text` (optional) maps paths to line numbers.
class Reader {
  public:
    Reader(std::string file, std::string_view text, bool inputsOnly = false)
        : m_file(std::move(file)), m_text(text), m_inputsOnly(inputsOnly) {}

    [[noreturn]] void fail(const JsonPath& at, const std::string& msg, bool namePath = true) const {
        int line = 0;
        if (!m_text.empty() && !at.empty()) {
            size_t offset = detail::findJsonValue(m_text, at);
            if (offset != std::string_view::npos) line = core::lineOfOffset(m_text, offset);
        }
        std::string where = detail::describe(at);
        throw core::Error(m_file, line, namePath && !where.empty() ? where + ": " + msg : msg);
    }

    // Requires `j` to be an object with exactly `keys`.
    void expectKeys(const json& j, const JsonPath& at, std::initializer_list<const char*> keys) {
        if (!j.is_object()) fail(at, std::string("expected an object, got ") + j.type_name());
        for (const char* key : keys)
            if (!j.contains(key)) fail(at, std::string("missing key '") + key + "'");
        for (const auto& item : j.items()) {
            bool known = std::any_of(keys.begin(), keys.end(),
                                     [&](const char* k) { return item.key() == k; });
            if (!known) fail(child(at, item.key()), "unknown key");
        }
    }
    std::string string(const json& obj, const JsonPath& at, const char* key) {
        const json& v = obj.at(key);
        if (!v.is_string())
            fail(child(at, key), std::string("expected a string, got ") + v.type_name());
        return v.get<std::string>();
    }
    double number(const json& obj, const JsonPath& at, const char* key) {
        const json& v = obj.at(key);
        if (!v.is_number())
            fail(child(at, key), std::string("expected a number, got ") + v.type_name());
        return v.get<double>();
    }
    const json& array(const json& obj, const JsonPath& at, const char* key) {
        const json& v = obj.at(key);
        if (!v.is_array())
            fail(child(at, key), std::string("expected an array, got ") + v.type_name());
        return v;
    }
    const json& object(const json& obj, const JsonPath& at, const char* key) {
        const json& v = obj.at(key);
        if (!v.is_object())
            fail(child(at, key), std::string("expected an object, got ") + v.type_name());
        return v;
    }
    void relativePath(const std::string& value, const JsonPath& at) {
        std::string problem = relativePathProblem(value);
        if (!problem.empty()) fail(at, "'" + value + "': " + problem);
    }
    void hash(const std::string& value, const JsonPath& at) {
        if (!isHash(value))
            fail(at, "'" + value + "' is not a content hash (expected fnv1a64: + 16 hex digits)");
    }

    int formatVersion(const json& j) {
        if (!j.is_object()) fail({}, std::string("expected a JSON object, got ") + j.type_name());
        if (!j.contains("formatVersion")) fail({}, "missing format version (key 'formatVersion')");
        const json& v = j.at("formatVersion");
        JsonPath at = child({}, "formatVersion");
        if (!v.is_number_integer())
            fail(at, std::string("expected an integer, got ") + v.type_name());
        auto version = v.get<long long>();
        if (version > kFormatVersion)
            fail(at,
                 "format version " + std::to_string(version) + " is newer than this program's " +
                     std::to_string(kFormatVersion),
                 false);
        if (version < 1)
            fail(at,
                 "format version " + std::to_string(version) +
                     " is not valid (versions start at 1)",
                 false);
        return static_cast<int>(version);
    }

    ModelFile model(const json& j, const JsonPath& at) {
        expectKeys(j, at, {"path", "hash", "source"});
        ModelFile m;
        m.path = string(j, at, "path");
        relativePath(m.path, child(at, "path"));
        m.hash = string(j, at, "hash");
        hash(m.hash, child(at, "hash"));
        m.source = string(j, at, "source");
        return m;
    }

    StageOutput output(const json& j, const JsonPath& at) {
        const bool stat = j.is_object() && j.contains("kind") && j["kind"].is_string() &&
                          isStatisticalKind(j["kind"].get<std::string>());
        const bool input = j.is_object() && j.contains("kind") && j["kind"].is_string() &&
                           isInputKind(j["kind"].get<std::string>());
        if (stat)
            expectKeys(j, at, {"stage", "file", "kind", "alpha", "tolNote", "hash"});
        else if (input)
            expectKeys(j, at, {"stage", "file", "kind", "tolNote", "hash"});
        else
            expectKeys(j, at, {"stage", "file", "kind", "absTol", "relTol", "tolNote", "hash"});
        StageOutput o;
        o.stage = string(j, at, "stage");
        if (!isValidName(o.stage))
            fail(child(at, "stage"),
                 "'" + o.stage + "' is not a valid stage name ([A-Za-z0-9_.-])");
        o.file = string(j, at, "file");
        relativePath(o.file, child(at, "file"));
        if (o.file == kManifestFileName) fail(child(at, "file"), "cannot be the manifest itself");
        o.kind = string(j, at, "kind");
        auto kinds = knownOutputKinds();
        if (std::find(kinds.begin(), kinds.end(), o.kind) == kinds.end()) {
            std::string known;
            for (const auto& k : kinds)
                known += (known.empty() ? "" : ", ") + k;
            fail(child(at, "kind"), "unknown output kind '" + o.kind + "' (known: " + known + ")");
        }
        if (stat) {
            o.alpha = number(j, at, "alpha");
            if (!(o.alpha > 0 && o.alpha < 1)) fail(child(at, "alpha"), "must lie in (0, 1)");
        } else if (!input) {
            o.absTol = number(j, at, "absTol");
            o.relTol = number(j, at, "relTol");
            for (const char* key : {"absTol", "relTol"}) {
                double t = j.at(key).get<double>();
                if (!(t >= 0) || !std::isfinite(t)) fail(child(at, key), "must be finite and >= 0");
            }
        }
        o.tolNote = string(j, at, "tolNote");
        o.hash = string(j, at, "hash");
        hash(o.hash, child(at, "hash"));
        return o;
    }

    Manifest manifest(const json& j) {
        Manifest m;
        m.formatVersion = formatVersion(j);
        expectKeys(j, {},
                   {"formatVersion", "name", "createdUtc", "programVersion", "glRenderer",
                    "glVersion", "models", "params", "settings", "outputs"});
        m.name = string(j, {}, "name");
        if (!isValidName(m.name))
            fail(child({}, "name"),
                 "'" + m.name + "' is not a valid capture name: " + nameProblem(m.name));
        m.createdUtc = string(j, {}, "createdUtc");
        m.programVersion = string(j, {}, "programVersion");
        m.glRenderer = string(j, {}, "glRenderer");
        m.glVersion = string(j, {}, "glVersion");
        m.params = object(j, {}, "params");
        m.settings = object(j, {}, "settings");

        std::set<std::string> seen;
        const json& models = array(j, {}, "models");
        for (size_t i = 0; i < models.size(); ++i) {
            JsonPath at = child(child({}, "models"), i);
            m.models.push_back(model(models[i], at));
            if (!seen.insert(m.models.back().path).second)
                fail(child(at, "path"), "'" + m.models.back().path + "' is listed twice");
        }
        const json& outputs = array(j, {}, "outputs");
        if (outputs.empty() && !m_inputsOnly)
            fail(child({}, "outputs"), "a capture needs at least one stage output");
        std::set<std::string> stages, files;
        for (size_t i = 0; i < outputs.size(); ++i) {
            JsonPath at = child(child({}, "outputs"), i);
            m.outputs.push_back(output(outputs[i], at));
            if (!stages.insert(m.outputs.back().stage).second)
                fail(child(at, "stage"), "stage '" + m.outputs.back().stage + "' is listed twice");
            if (!files.insert(m.outputs.back().file).second)
                fail(child(at, "file"), "file '" + m.outputs.back().file + "' is used twice");
        }
        return m;
    }

  private:
    std::string m_file;
    std::string_view m_text;
    bool m_inputsOnly = false; // a record request: no outputs yet
};

// "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..." ->
// "syntax error ..."
std::string parseErrorMessage(const std::string& what) {
    size_t column = what.find(", column ");
    if (column != std::string::npos) {
        size_t colon = what.find(": ", column);
        if (colon != std::string::npos) return what.substr(colon + 2);
    }
    size_t bracket = what.find("] ");
    return bracket != std::string::npos ? what.substr(bracket + 2) : what;
}

} // namespace

std::vector<std::string> knownOutputKinds() {
    return {"csv", "csv_stat", "exr_stat", "exr", "exr_input"};
}

bool isInputKind(std::string_view kind) {
    return kind == "exr_input";
}

bool isStatisticalKind(std::string_view kind) {
    return kind == "csv_stat" || kind == "exr_stat";
}

std::string nameProblem(std::string_view name) {
    if (name.empty()) return "a name is needed";
    if (name.front() == '.' || name.front() == '-')
        return "starts with '" + std::string(1, name.front()) +
               "' (a name starts with a letter, a digit or '_')";
    const bool allowed = std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == '-' || c == '.';
    });
    return allowed ? "" : "letters, digits, '_', '-' and '.' only";
}

bool isValidName(std::string_view name) {
    return nameProblem(name).empty();
}

bool isHash(std::string_view text) {
    constexpr std::string_view prefix = "fnv1a64:";
    if (text.size() != prefix.size() + 16 || text.substr(0, prefix.size()) != prefix) return false;
    return std::all_of(text.begin() + prefix.size(), text.end(),
                       [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

std::string relativePathProblem(std::string_view path) {
    if (path.empty()) return "empty path";
    if (path.find('\\') != std::string_view::npos) return "use '/' as the separator";
    if (path.find(':') != std::string_view::npos) return "':' is not allowed in paths";
    if (path.front() == '/') return "absolute paths are not allowed";
    size_t start = 0;
    while (start <= path.size()) {
        size_t end = path.find('/', start);
        if (end == std::string_view::npos) end = path.size();
        std::string_view part = path.substr(start, end - start);
        if (part.empty()) return "empty path component";
        if (part == "..") return "'..' would escape the folder";
        if (part == ".") return "'.' components are not allowed";
        start = end + 1;
    }
    return "";
}

std::string utcNow() {
    std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buf;
}

nlohmann::json toJson(const Manifest& m) {
    json j = json::object();
    j["formatVersion"] = m.formatVersion;
    j["name"] = m.name;
    j["createdUtc"] = m.createdUtc;
    j["programVersion"] = m.programVersion;
    j["glRenderer"] = m.glRenderer;
    j["glVersion"] = m.glVersion;
    j["models"] = json::array();
    for (const ModelFile& f : m.models)
        j["models"].push_back({{"path", f.path}, {"hash", f.hash}, {"source", f.source}});
    j["params"] = m.params;
    j["settings"] = m.settings;
    j["outputs"] = json::array();
    for (const StageOutput& o : m.outputs) {
        json out = {{"stage", o.stage},
                    {"file", o.file},
                    {"kind", o.kind},
                    {"tolNote", o.tolNote},
                    {"hash", o.hash}};
        if (isStatisticalKind(o.kind)) {
            out["alpha"] = o.alpha;
        } else if (!isInputKind(o.kind)) {
            out["absTol"] = o.absTol;
            out["relTol"] = o.relTol;
        }
        j["outputs"].push_back(std::move(out));
    }
    return j;
}

Manifest fromJson(const nlohmann::json& j, const std::string& fileForErrors) {
    Reader reader(fileForErrors, {});
    return reader.manifest(j);
}

namespace {
// A manifest (or, inputsOnly, a record request) from its file, errors at their JSON line.
Manifest readFile(const std::filesystem::path& file, bool inputsOnly) {
    const std::string fileName = file.string();
    const std::string text = core::readFile(file);
    json j;
    try {
        j = json::parse(text);
    } catch (const json::parse_error& e) {
        size_t offset = e.byte > 0 ? e.byte - 1 : 0;
        throw core::Error(fileName, core::lineOfOffset(text, offset),
                          "invalid JSON: " + parseErrorMessage(e.what()));
    } catch (const json::exception& e) {
        // e.g. out_of_range 406: a number too large for a double ("1e999")
        throw core::Error(fileName, 0, "invalid JSON: " + parseErrorMessage(e.what()));
    }
    return Reader(fileName, text, inputsOnly).manifest(j);
}
} // namespace

Manifest readInputs(const std::filesystem::path& file) {
    return readFile(file, true);
}

void writeInputs(const std::filesystem::path& file, const Manifest& manifest) {
    const json j = toJson(manifest);
    Reader(file.string(), {}, true).manifest(j); // refuse to write what could not be read back
    core::writeFile(file, j.dump(2) + "\n");
}

Manifest readManifest(const std::filesystem::path& captureDir) {
    const std::filesystem::path file = captureDir / kManifestFileName;
    const std::string fileName = file.string();
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) {
        if (!std::filesystem::is_directory(captureDir, ec))
            throw core::Error(fileName, 0,
                              "missing: there is no capture folder " + captureDir.string());
        throw core::Error(fileName, 0, "missing (every capture folder needs a manifest.json)");
    }
    return readFile(file, false);
}

void writeManifest(const std::filesystem::path& captureDir, const Manifest& manifest) {
    const std::filesystem::path file = captureDir / kManifestFileName;
    const json j = toJson(manifest);
    Reader(file.string(), {}).manifest(j); // refuse to write what could not be read back
    std::string text;
    try {
        text = j.dump(2) + "\n";
    } catch (const json::exception& e) {
        throw core::Error(file.string(), 0, std::string("cannot serialise: ") + e.what());
    }
    std::error_code ec;
    std::filesystem::create_directories(captureDir, ec);
    if (ec) throw core::Error(captureDir.string(), 0, "cannot create folder: " + ec.message());
    core::writeFile(file, text);
}

} // namespace capture
