// A new model for its author to edit (File → New model, `new-model`): materials/NAME.bssrdf
// made from an existing model's text (by default the classical dipole, materials/dipole.bssrdf:
// a working model with parameters, an initializer, DiffuseReflectance and Bssrdf to change),
// its first line a comment naming where it came from. A workbench watching materials/ loads it
// as it appears and at every save; a model is never overwritten.
#pragma once

#include <filesystem>
#include <string>

namespace app {

// The model a new one is made from when none is given.
inline constexpr const char* kNewModelTemplate = "materials/dipole.bssrdf";

// What is wrong with NAME as a new model's name under `root` ("" when nothing): not a file
// name (letters, digits, '_', '-', '.', not starting with '.' or '-'), or a model of that name
// already in materials/. A trailing ".bssrdf" is allowed and ignored.
std::string newModelProblem(const std::filesystem::path& root, std::string name);

// Writes <root>/materials/NAME.bssrdf from the text of `from` and returns it. Throws
// core::Error naming the name (newModelProblem) or the file `from` (missing, not a model).
std::filesystem::path createModel(const std::filesystem::path& root, std::string name,
                                  const std::filesystem::path& from);

} // namespace app
