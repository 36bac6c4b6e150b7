// The program's exit statuses, every command's and the model check's, in one place:
//   0                  success
//   1                  a bad input, file or run (`error: …` on stderr names it)
//   kUsageError        a command line the parser refused
//   kEnergyCheckFailed a result that failed its own check (its output is still written): a
//                      path-traced energy balance, or a model profile with NaN, Inf or negative
//                      values
//   kProbeLoopCut      `probe-model`: a loop in the model was cut short by the driver's
//                      iteration limit (probe/protocol.h)
//   kProbeUnavailable  `probe-model`, `probe-server`: no headless GL context to check with
//   kNotConverged      `fit`: the optimizer stopped before converging (its evaluation budget);
//                      the best point found is still written
#pragma once

namespace app {

constexpr int kUsageError = 2;
constexpr int kEnergyCheckFailed = 3;
constexpr int kProbeLoopCut = 4;
constexpr int kProbeUnavailable = 5;
constexpr int kNotConverged = 6;

} // namespace app
