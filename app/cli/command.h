// The command table: every command of the program as one entry — its name, its one-line help,
// and a function that declares its options on the parser and returns what runs when the command
// is chosen. Each command's entry is made in its own file (a `Command fooCommand()` beside the
// command's code) and registered by one line in commands.cpp; main.cpp only calls
// runCommandLine. How to add one: docs/ARCHITECTURE.md, "How to add a command".
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace app {

// What a running command may ask for. The project root (materials/ and shaders/) is looked for
// only when a command first asks for it, so commands that read no project file run anywhere.
class CommandContext {
  public:
    explicit CommandContext(std::string rootArg) : m_rootArg(std::move(rootArg)) {}
    // --root, $BSSRDF_WORKBENCH_ROOT, the installed layout beside the executable, the nearest
    // folder above the executable holding both, or the current folder; core::Error otherwise.
    const std::filesystem::path& root();

  private:
    std::string m_rootArg;
    std::optional<std::filesystem::path> m_root;
};

using CommandRun = std::function<int(CommandContext&)>;

struct Command {
    std::string name; // as typed: "slab"; a subcommand of a group: "bench reload"
    std::string help; // one line in --help
    bool hidden = false;
    // Declares the command's options on its parser (into state the returned function owns) and
    // returns what runs when the command is chosen. Empty for a group (its subcommands run).
    std::function<CommandRun(CLI::App&)> declare;
};

// Every command, in the order --help lists them (commands.cpp).
const std::vector<Command>& commands();

// Parses the command line, runs the chosen command (none: the first, `gui`) and returns the
// exit status (common/exit_codes.h): a refused command line prints `error: …` and returns
// kUsageError, a core::Error or other exception from a command prints `error: …` and returns 1.
int runCommandLine(int argc, char** argv);

} // namespace app
