// The `bench` group: one command per benchmark (bench/), each declaring its options here and
// running the benchmark's function. Benchmarks print measured numbers and ratios; tests never
// assert times.
#include "bench/bench.h"
#include "cli/command.h"
#include "cli/options.h"
#include "core/core.h"

#include <cstdio>
#include <memory>

namespace app {

namespace {
// each line as it is measured, also into a file or pipe: a bench stopped by a time limit (or
// Ctrl-C) keeps what it printed
void lineBuffered() {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
}
} // namespace

Command benchGroup() {
    return {"bench", "benchmarks (print measured ratios; not tests)", false, {}};
}

Command benchReloadCommand() {
    return {"bench reload", "hot reload: save -> new pixels latency", false,
            [](CLI::App& cmd) -> CommandRun {
                auto runs = std::make_shared<int>(10);
                cmd.add_option("--runs", *runs, "edits to time (default 10)")
                    ->check(CLI::Range(1, 1000));
                return [runs](CommandContext& ctx) {
                    lineBuffered();
                    return benchReload(ctx.root(), *runs);
                };
            }};
}

Command benchPathtraceCommand() {
    return {"bench pathtrace", "path tracer: paths/s and time to 1% error", false,
            [](CLI::App& cmd) -> CommandRun {
                auto seconds = std::make_shared<double>(4.0);
                auto mcml = std::make_shared<std::string>();
                cmd.add_option("--seconds", *seconds, "seconds per case and tracer (default 4)")
                    ->check(CLI::Range(0.05, 600.0));
                cmd.add_option("--mcml", *mcml,
                               "MCML 1.2.2's mcml binary: time it here on the reference case "
                               "(2e6 photons) beside our tracer");
                return [seconds, mcml](CommandContext& ctx) {
                    lineBuffered();
                    return benchPathtrace(ctx.root(), *seconds, *mcml);
                };
            }};
}

Command benchSamplingCommand() {
    return {"bench sampling",
            "BSSRDF integration: equal-time error of disk importance vs uniform sampling", false,
            [](CLI::App& cmd) -> CommandRun {
                struct Args {
                    double seconds = 2.0, reference = 10.0;
                    int size = 48;
                };
                auto a = std::make_shared<Args>();
                cmd.add_option("--seconds", a->seconds, "seconds per method and case (default 2)")
                    ->check(CLI::Range(0.05, 600.0));
                cmd.add_option("--size", a->size, "image side in pixels (default 48)")
                    ->check(CLI::Range(4, 1024));
                cmd.add_option("--reference-factor", a->reference,
                               "the reference runs this many times longer (default 10)")
                    ->check(CLI::Range(1.0, 1000.0));
                return [a](CommandContext& ctx) {
                    lineBuffered();
                    return benchSampling(ctx.root(), a->seconds, a->size, a->reference);
                };
            }};
}

Command benchConvergenceCommand() {
    return {"bench convergence", "error against time of the Render panel's renderers, log-log plot",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<ConvergenceBenchOptions>();
                cmd.add_option("--preset", a->preset, "material preset (default Marble)");
                cmd.add_option("--width", a->width, "frame width (default 160)")
                    ->check(CLI::Range(8, 4096));
                cmd.add_option("--height", a->height, "frame height (default 90)")
                    ->check(CLI::Range(8, 4096));
                cmd.add_option("--points", a->points, "point-cloud points (default 50000)")
                    ->check(CLI::Range(100, 10000000));
                cmd.add_option("--reference-spp", a->referenceSpp,
                               "samples per pixel of the converged image (default 1024)")
                    ->check(CLI::Range(1, 1000000));
                cmd.add_option("--max-spp", a->maxSpp, "last Monte Carlo point (default 256)")
                    ->check(CLI::Range(1, 1000000));
                cmd.add_option("--out", a->out, "folder for convergence.csv and convergence.png");
                return [a](CommandContext& ctx) {
                    lineBuffered();
                    return benchConvergence(ctx.root(), *a);
                };
            }};
}

Command benchTextureSpaceCommand() {
    return {
        "bench texture-space", "texture-space sampling vs the hierarchical render at equal error",
        false, [](CLI::App& cmd) -> CommandRun {
            auto a = std::make_shared<TextureSpaceBenchOptions>();
            cmd.add_option("--presets", a->presets, "material presets (default Marble Skin1)");
            cmd.add_option("--scales", a->scalesMm, "model sizes in mm (default 10 50)");
            cmd.add_option("--samples", a->samples, "N values (default 49 100 400 900 1600 2500)");
            cmd.add_option("--textures", a->textures, "texture sizes (default 16 64 256 1024)");
            cmd.add_option("--eps", a->eps, "hierarchical eps values (default 64 … 1)");
            cmd.add_option("--points", a->points, "point-cloud points (default 50000)")
                ->check(CLI::Range(100, 10000000));
            cmd.add_option("--width", a->width, "frame width (default 160)")
                ->check(CLI::Range(8, 4096));
            cmd.add_option("--height", a->height, "frame height (default 90)")
                ->check(CLI::Range(8, 4096));
            cmd.add_option("--sets", a->sets, "sample sets per case (default 4)")
                ->check(CLI::Range(1, 10000));
            return [a](CommandContext& ctx) {
                lineBuffered();
                const std::filesystem::path& root = ctx.root();
                for (int k : a->textures)
                    if (k < 16 || k > 2048 || (k & (k - 1)) != 0)
                        throw core::Error("--textures", 0,
                                          "each must be a power of two in [16, 2048]");
                for (int n : a->samples)
                    if (n < 1 || n > (1 << 20))
                        throw core::Error("--samples", 0, "each must lie in [1, 1048576]");
                return benchTextureSpace(root, *a);
            };
        }};
}

Command benchHierarchyCommand() {
    return {"bench hierarchy", "hierarchical vs brute-force render, point-cloud generation vs Turk",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<HierarchyBenchOptions>();
                cmd.add_option("--points", a->points, "points (default 100000)");
                addEnumOption(&cmd, "--method", a->method,
                              std::string("point-cloud method (default ") +
                                  pointcloud::methodName(a->method) + ")");
                cmd.add_option("--width", a->width, "image width (default 640)");
                cmd.add_option("--height", a->height, "image height (default 360)");
                cmd.add_option("--frames", a->frames, "hierarchical frames per eps (default 5)")
                    ->check(CLI::Range(1, 1000));
                cmd.add_option("--brute-frames", a->bruteFrames, "brute-force frames (default 3)")
                    ->check(CLI::Range(1, 1000));
                cmd.add_option(
                       "--turk-iterations", a->turkIterations,
                       "Turk repulsion iterations of the reference cloud (default 500, 0: skip)")
                    ->check(CLI::Range(0, 100000));
                cmd.add_option("--eps", a->eps,
                               "solid-angle criterion eps values (default 0.8 0.4 0.2 0.1)");
                cmd.add_option("--box-eps", a->boxEps,
                               "bounding-box criterion eps values (default 12.8 6.4 3.2 1.6)");
                return [a](CommandContext& ctx) {
                    lineBuffered();
                    return benchHierarchy(ctx.root(), *a);
                };
            }};
}

} // namespace app
