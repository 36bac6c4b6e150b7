// `bssrdf-workbench defaults`: every workbench setting with its default and meaning, from the
// settings descriptions (core/fields.h), as the README's "Defaults" section shows it.
#include "cli/defaults_command.h"

#include "cli/command.h"
#include "pipeline/settings_sections.h"

#include <cstdio>

namespace app {

std::string defaultsTable() {
    std::string out = "| setting | default | meaning |\n|---|---|---|\n";
    for (const SettingsSection& s : settingsSections(nullptr))
        s.forEachDefault([&](const std::string& path, const std::string& value, const char* doc) {
            out += "| `" + path + "` | " + value + " | " + doc + " |\n";
        });
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
