// Output checks every command runs before any work (so a long run never ends in "cannot write"):
// the folder exists and takes a file, and a binary format's file name has its extension.
#pragma once

#include <string>

namespace app {

// core::Error naming `flag` and the path when `path` cannot be created: its folder must exist
// and accept a file. An empty path passes (the output is optional).
void checkWritable(const std::string& path, const std::string& flag);
// checkWritable, and the file name must end in `extension` (".exr", case-insensitive), since the
// content is that format whatever the name says.
void checkOutput(const std::string& path, const std::string& flag, const std::string& extension);

} // namespace app
