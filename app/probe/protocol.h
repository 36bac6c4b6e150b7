// What the model check's child process (`probe-model`, `probe-server`: cli/probe_commands.h) and
// its parent (model_probe_process.h) say to each other: the tag that starts each line the child
// prints, the separators of a request to the warm server, and the exit statuses that mean
// something to the parent (common/exit_codes.h).
#pragma once

#include "common/exit_codes.h"

namespace app {

inline constexpr const char* kProbeTag = "probe-model:";
inline constexpr char kProbeFieldSeparator = '\x1f'; // ASCII unit separator
inline constexpr char kProbeRequestEnd = '\x1e';     // ASCII record separator

} // namespace app
