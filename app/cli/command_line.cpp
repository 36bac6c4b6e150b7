// The command line: the program's own options, one parser subcommand per entry of the command
// table (command.h), the parse with its errors in the one form every error takes, and the run.
#include "cli/command.h"

#include "cli/options.h"
#include "common/exit_codes.h"
#include "core/core.h"
#include "probe/child_process.h"
#include "probe/model_probe_process.h"

#include <cstdio>
#include <cstdlib>
#include <map>

namespace app {
namespace fs = std::filesystem;

namespace {

// Never a tree found only by where the binary was built: a copied build must say it found
// nothing rather than silently read another checkout.
fs::path findRoot(const std::string& given) {
    auto ok = [](const fs::path& p) {
        std::error_code ec;
        return fs::is_directory(p / "materials", ec) && fs::is_directory(p / "shaders", ec);
    };
    if (!given.empty()) {
        if (!ok(given))
            throw core::Error(given, 0, "--root: expected a folder with materials/ and shaders/");
        return fs::absolute(given).lexically_normal();
    }
    if (const char* env = std::getenv("BSSRDF_WORKBENCH_ROOT"); env && *env) {
        if (!ok(env))
            throw core::Error(env, 0,
                              "$BSSRDF_WORKBENCH_ROOT: expected a folder with materials/ and "
                              "shaders/");
        return fs::absolute(env).lexically_normal();
    }
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path bin = exe.parent_path();
        // the installed layout: <prefix>/share/bssrdf-workbench for <prefix>/bin/...
        if (ok(bin.parent_path() / "share" / "bssrdf-workbench"))
            return bin.parent_path() / "share" / "bssrdf-workbench";
        for (fs::path d = bin; !d.empty(); d = d.parent_path()) {
            if (ok(d)) return d;
            if (d == d.root_path()) break;
        }
    }
    if (ok(fs::current_path())) return fs::current_path();
    throw core::Error(exe.empty() ? "bssrdf-workbench" : exe.string(), 0,
                      "cannot find materials/ and shaders/ beside the executable or in the "
                      "current folder; pass --root DIR (or set $BSSRDF_WORKBENCH_ROOT)");
}

// The names a parser offers, comma-separated, hidden ones left out.
std::string offered(const CLI::App& parent) {
    std::string names;
    for (const CLI::App* sub : parent.get_subcommands(
             [](const CLI::App* a) { return !a->get_name().empty() && !a->get_group().empty(); }))
        names += (names.empty() ? "" : ", ") + sub->get_name();
    return names;
}

// A refused command line in the words of this program where the parser's own would not name
// what to type: a group ("bench") without one of its commands and a word that is no command.
std::string usageMessage(const CLI::App& cli, const std::map<std::string, CLI::App*>& parsers,
                         const CLI::ParseError& e) {
    for (const Command& c : commands()) {
        const CLI::App* group = parsers.at(c.name);
        if (c.declare || !group->parsed() || !group->get_subcommands().empty()) continue;
        const std::vector<std::string> extra = group->remaining();
        return extra.empty() ? c.name + ": give one of " + offered(*group)
                             : c.name + " " + extra.front() + ": not a command of " + c.name +
                                   "; give one of " + offered(*group);
    }
    const std::vector<std::string> extra = cli.remaining();
    if (dynamic_cast<const CLI::ExtrasError*>(&e) && cli.get_subcommands().empty() &&
        !extra.empty() && extra.front().rfind('-', 0) != 0)
        return extra.front() + ": not a command; the commands are " + offered(cli);
    return e.what();
}

} // namespace

const fs::path& CommandContext::root() {
    if (!m_root) m_root = findRoot(m_rootArg);
    return *m_root;
}

int runCommandLine(int argc, char** argv) {
    CLI::App cli{"bssrdf-workbench " BW_VERSION
                 " — develop, inspect and validate analytic BSSRDF models"};
    cli.require_subcommand(0, 1);
    std::string rootArg;
    bool verbose = false;
    cli.add_option("--root", rootArg, "project root holding materials/ and shaders/");
    cli.add_flag("-v,--verbose", verbose, "echo info messages to stderr");

    // one parser per command; a group's subcommands ("bench reload") under the group's parser
    std::map<std::string, CLI::App*> parsers;
    std::vector<std::pair<CLI::App*, CommandRun>> runs;
    for (const Command& c : commands()) {
        const size_t space = c.name.find(' ');
        CLI::App* parent = space == std::string::npos ? &cli : parsers.at(c.name.substr(0, space));
        CLI::App* cmd = parent->add_subcommand(
            space == std::string::npos ? c.name : c.name.substr(space + 1), c.help);
        if (c.hidden) cmd->group("");
        parsers[c.name] = cmd;
        if (c.declare)
            runs.emplace_back(cmd, c.declare(*cmd));
        else
            cmd->require_subcommand(1); // a group: one of its subcommands runs
    }

    // Command-line errors in the one form every error takes, `error: <argument>: message`, with
    // exit status 2 (usage); help and version exit 0 as the parser prints them.
    refuseNonFiniteNumbers(cli);
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s\n(run with --help for the options)\n",
                     usageMessage(cli, parsers, e).c_str());
        return kUsageError;
    }
    if (verbose) core::setLogEchoLevel(core::LogLevel::Info);
    // Every model a Workbench loads is first evaluated by this executable in a child process.
    setModelProbeExecutable(selfExecutable());

    CommandContext context(rootArg);
    try {
        CommandRun* chosen = &runs.front().second; // no command: the first (gui)
        for (auto& [cmd, run] : runs)
            if (*cmd) {
                chosen = &run;
                break;
            }
        const int rc = (*chosen)(context);
        core::progressEnd(); // a progress line the command left open
        return rc;
    } catch (const std::exception& e) {
        core::progressEnd();
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}

} // namespace app
