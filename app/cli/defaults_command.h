// The defaults of every workbench setting as a Markdown table (`bssrdf-workbench defaults`; the
// README's "Defaults" section is this text): setting, default, meaning.
#pragma once

#include <string>

namespace app {

std::string defaultsTable();

} // namespace app
