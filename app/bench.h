// Benchmarks (`bssrdf-workbench bench NAME`): print measured numbers and ratios to targets.
// Tests never assert times; these are for people and CI logs.
#pragma once

#include <filesystem>

namespace app {

// bench reload: save → new pixels latency of hot reload on a 512-sample pencil plot, through
// the real watcher, parser, GLSL compile, GPU evaluation and a full headless UI frame.
int benchReload(const std::filesystem::path& root, int runs);

} // namespace app
