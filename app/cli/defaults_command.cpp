// `bssrdf-workbench defaults`: every workbench setting with its default and meaning, from the
// settings descriptions (core/fields.h), as the README's "Defaults" section shows it.
#include "cli/defaults_command.h"

#include "cli/command.h"
#include "cli/options.h"
#include "core/fields.h"
#include "pipeline/workbench.h"

#include <cstdio>

namespace app {

std::string defaultsTable() {
    std::string out = "| setting | default | meaning |\n|---|---|---|\n";
    auto rows = [&](auto s, const std::string& prefix) {
        core::forEachField(
            s,
            [&](const std::string& path, const auto& m, const char* doc) {
                out += "| `" + path + "` | " + defaultText(m) + " | " + doc + " |\n";
            },
            prefix);
    };
    rows(MaterialSettings{}, "material.");
    rows(PlotSettings{}, "plot.");
    rows(ReferenceSettings{}, "reference.");
    rows(SliceSettings{}, "slice.");
    rows(LitSphereSettings{}, "lit_spheres.");
    rows(SceneSettings{}, "scene.");
    rows(MonteCarloSettings{}, "monte_carlo.");
    rows(TextureSpaceSettings{}, "texture_space.");
    return out;
}

Command defaultsCommand() {
    return {"defaults", "print every setting's default (GUI, CLI and captures) as a Markdown table",
            false, [](CLI::App&) -> CommandRun {
                return [](CommandContext&) {
                    std::fputs(defaultsTable().c_str(), stdout);
                    return 0;
                };
            }};
}

} // namespace app
