// Output checks every command runs before any work (so a long run never ends in "cannot write"):
// the folder exists and takes a file, and a binary format's file name has its extension. And the
// rate a progress line shows.
#pragma once

#include <cstdint>
#include <string>

namespace app {

// core::Error naming `flag` and the path when `path` cannot be created: its folder must exist
// and accept a file. An empty path passes (the output is optional).
void checkWritable(const std::string& path, const std::string& flag);
// checkWritable, and the file name must end in `extension` (".exr", case-insensitive), since the
// content is that format whatever the name says.
void checkOutput(const std::string& path, const std::string& flag, const std::string& extension);

// "123456 paths/s" for `done` paths in `seconds`; "-- paths/s" until there is a rate to show
// (nothing done yet, or under a tenth of a second: no "0 paths/s" at the start of a run).
std::string pathRate(uint64_t done, double seconds);
// The progress line of a path-traced run on stderr, rewritten in place:
// "\r<what>: 12.5%  1000 / 8000 paths  123456 paths/s" (100 % when total is 0).
void printPathProgress(const char* what, uint64_t done, uint64_t total, double seconds);

} // namespace app
