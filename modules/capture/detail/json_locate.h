// Finds where a value sits in JSON text, so validation errors about an already parsed
// document (nlohmann::json keeps no positions) can name the line of the offending key.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace capture::detail {

// One step into a JSON document: an object key or an array index.
struct JsonStep {
    std::string key;
    size_t index = 0;
    bool isIndex = false;
};
using JsonPath = std::vector<JsonStep>;

// "outputs[1].relTol"; "" for the document itself.
std::string describe(const JsonPath& path);
// Byte offset of the first character of the value at `path` in `text` (which must be valid
// JSON), or std::string_view::npos when it is not found.
size_t findJsonValue(std::string_view text, const JsonPath& path);

} // namespace capture::detail
