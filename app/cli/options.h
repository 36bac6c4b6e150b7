// Command-line options generated from settings descriptions (core/fields.h): a setting on the
// command line gets its flag from a table, its help text from the description and its default
// from the struct it writes into (which holds the GUI's defaults), so the CLI cannot drift.
//   bool           "--flag" sets it, "--no-flag" clears it (or the table's own "!--x")
//   enum           its names (core::enumNames)
//   number/string  the value; a number must be finite and inside the setting's core::Limits
//                  (the same check the JSON reader makes), else it is refused naming the flag
#pragma once

#include "core/fields.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace app {

// A setting's value as the help text shows it (core/fields.h).
using core::defaultText;

// An option taking one of the names of enum E.
template <core::NamedEnum E>
void addEnumOption(CLI::App* cmd, const std::string& flag, E& m, const std::string& help) {
    cmd->add_option_function<std::string>(
        flag,
        [&m, flag](const std::string& v) {
            for (const auto& [e, n] : enumNames(E{}))
                if (v == n) {
                    m = e;
                    return;
                }
            throw CLI::ValidationError(flag, "unknown name '" + v + "' (expected " +
                                                 core::enumNameList<E>() + ")");
        },
        help + ": " + core::enumNameList<E>());
}

// An integer option that also takes exact scientific notation ("1e6", "2.5e3"): anything that
// is not an integer within M's range and `lim` is refused naming the flag.
template <class M>
CLI::Option* addCountOption(CLI::App* cmd, const std::string& flag, M& m, const std::string& help,
                            core::Limits lim = {}) {
    return cmd
        ->add_option_function<std::string>(
            flag,
            [&m, flag, lim](const std::string& v) {
                char* end = nullptr;
                const long double x = std::strtold(v.c_str(), &end);
                const bool parsed = !v.empty() && end == v.c_str() + v.size();
                if (!parsed || !(x == std::floor(x)) ||
                    x < static_cast<long double>(std::numeric_limits<M>::min()) ||
                    x > static_cast<long double>(std::numeric_limits<M>::max()))
                    throw CLI::ValidationError(flag, "expected a whole number (e.g. 1000000 or "
                                                     "1e6) within range, got '" +
                                                         v + "'");
                if (std::string p = core::limitProblem(static_cast<M>(x), lim); !p.empty())
                    throw CLI::ValidationError(flag, p);
                m = static_cast<M>(x);
            },
            help)
        ->type_name("INT");
}

template <class M> struct OptionalValue { using type = M; };
template <class M> struct OptionalValue<std::optional<M>> { using type = M; };

// A floating-point option (M a number or std::optional of one): the whole argument must be a finite
// number inside `lim` ("nan", "inf", "1e999" and "2x" are refused naming the flag, never replaced
// by a default).
template <class M>
CLI::Option* addNumberOption(CLI::App* cmd, const std::string& flag, M& m, const std::string& help,
                             core::Limits lim = {}) {
    return cmd
        ->add_option_function<std::string>(
            flag,
            [&m, flag, lim](const std::string& v) {
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                if (v.empty() || end != v.c_str() + v.size())
                    throw CLI::ValidationError(flag, "expected a number, got '" + v + "'");
                using Value = typename OptionalValue<M>::type;
                if (std::string p = core::limitProblem(static_cast<Value>(x), lim); !p.empty())
                    throw CLI::ValidationError(flag, p);
                m = static_cast<Value>(x);
            },
            help)
        ->type_name("FLOAT");
}

// Every option of `cmd` and its subcommands whose values are floating-point numbers (CLI11's
// type name FLOAT, whatever added it) refuses "nan", "inf" and numbers beyond double's range
// naming the flag. Run once on the finished command line, before parsing.
inline void refuseNonFiniteNumbers(CLI::App& cmd) {
    for (CLI::Option* o : cmd.get_options()) {
        if (o->get_type_name().rfind("FLOAT", 0) != 0) continue;
        o->check(
            [](const std::string& v) -> std::string {
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                if (v.empty() || end != v.c_str() + v.size())
                    return "expected a number, got '" + v + "'";
                if (!std::isfinite(x)) return "must be a finite number, got '" + v + "'";
                return "";
            },
            "", "finite");
    }
    for (CLI::App* sub : cmd.get_subcommands([](CLI::App*) { return true; }))
        refuseNonFiniteNumbers(*sub);
}

// Options that the mode a command line chose would ignore, refused instead (exit 2, as
// "<flag>: <why>"): each rule's flags, when given while `applies()` holds after the parse.
// One call per command (it sets the command's parse-complete callback).
struct IgnoredOptions {
    std::vector<std::string> flags;
    std::function<bool()> applies; // reads the parsed values
    std::string why;               // "only with --renderer hybrid"
};
inline void refuseIgnoredOptions(CLI::App* cmd, std::vector<IgnoredOptions> rules) {
    cmd->parse_complete_callback([cmd, rules = std::move(rules)] {
        for (const IgnoredOptions& rule : rules)
            for (const std::string& flag : rule.flags)
                if (cmd->get_option(flag)->count() > 0 && rule.applies())
                    throw CLI::ValidationError(flag, rule.why);
    });
}

// --threads of every command: 0 (the default) uses all hardware threads.
inline constexpr core::Limits kThreadLimits{0, 1024};

struct SettingFlag {
    const char* path; // in the description: "render.eps", "points.count"
    std::string flag; // "--eps"; for a bool also "!--off-flag" after a comma
};

// Adds one option per entry of `flags` to `cmd`, writing into `s`. Throws std::logic_error for
// an entry whose path the description of T does not have.
template <class T>
void addSettingOptions(CLI::App* cmd, T& s, const std::vector<SettingFlag>& flags) {
    std::vector<bool> used(flags.size(), false);
    core::forEachField(s, [&](const std::string& path, auto& m, const char* doc, core::Limits lim) {
        using M = std::remove_reference_t<decltype(m)>;
        for (size_t i = 0; i < flags.size(); ++i) {
            if (path != flags[i].path) continue;
            used[i] = true;
            const std::string help = std::string(doc) + " (default " + defaultText(m) + ")";
            std::string flag = flags[i].flag;
            if constexpr (std::is_same_v<M, bool>) {
                if (flag.find('!') == std::string::npos) flag += ",!--no-" + flag.substr(2);
                cmd->add_flag(flag, m, help);
            } else if constexpr (core::NamedEnum<M>) {
                addEnumOption(cmd, flag, m, help);
            } else if constexpr (std::is_integral_v<M>) {
                addCountOption(cmd, flag, m, help, lim);
            } else if constexpr (std::is_floating_point_v<M>) {
                addNumberOption(cmd, flag, m, help, lim);
            } else if constexpr (std::is_same_v<M, std::string>) {
                cmd->add_option(flag, m, help);
            } else {
                throw std::logic_error("no command-line form for " + path);
            }
        }
    });
    for (size_t i = 0; i < flags.size(); ++i)
        if (!used[i])
            throw std::logic_error(std::string("no setting '") + flags[i].path + "' for " +
                                   flags[i].flag);
}

} // namespace app
