// Shared by the libFuzzer targets of tests/fuzz: the input written to a per-process scratch
// file (for readers that take a path) and the one accepted failure, core::Error, whose message
// must be printable (no raw control or invalid UTF-8 bytes copied from the input).
#pragma once

#include "core/core.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>

namespace fuzz {

// A folder of this process under the temp dir, made on first use.
inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        std::filesystem::path d =
            std::filesystem::temp_directory_path() / ("bw-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

// Writes the input to scratchDir()/name and returns that path.
inline std::filesystem::path writeInput(const uint8_t* data, size_t size, const std::string& name) {
    std::filesystem::path p = scratchDir() / name;
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) {
        std::fprintf(stderr, "fuzz: cannot write %s\n", p.c_str());
        std::abort();
    }
    return p;
}

inline std::string_view asText(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

// Aborts (a finding) when an error message carries a byte a terminal would not show as text.
inline void checkMessage(const core::Error& e) {
    if (!core::isPrintableText(e.what())) {
        std::fprintf(stderr, "fuzz: unprintable bytes in the error message\n");
        std::abort();
    }
}

// Runs f(); a core::Error is a clean outcome (its message checked), anything else escapes.
template <class F> void expectCleanError(F&& f) {
    try {
        f();
    } catch (const core::Error& e) {
        checkMessage(e);
    }
}

} // namespace fuzz
