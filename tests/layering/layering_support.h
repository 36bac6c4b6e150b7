// What the layering tests of modules/ (layering_test.cpp) and app/ (app_layering_test.cpp)
// share: the allowed-dependency graph, reading a file, the cycle check, a scratch tree.
#pragma once

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <unistd.h>

namespace layering {
namespace fs = std::filesystem;
using Graph = std::map<std::string, std::set<std::string>>;

inline std::string readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// True when the graph has no cycle (so an order exists in which every arrow points down).
inline bool acyclic(const Graph& g) {
    std::map<std::string, int> state; // 0 new, 1 on the stack, 2 done
    std::function<bool(const std::string&)> visit = [&](const std::string& n) {
        if (state[n] == 1) return false;
        if (state[n] == 2) return true;
        state[n] = 1;
        auto it = g.find(n);
        if (it != g.end())
            for (const auto& d : it->second)
                if (!visit(d)) return false;
        state[n] = 2;
        return true;
    };
    for (const auto& [n, deps] : g)
        if (!visit(n)) return false;
    return true;
}

struct TempTree {
    fs::path root = fs::temp_directory_path() / ("bw_layering_" + std::to_string(::getpid()));
    TempTree() { fs::remove_all(root); }
    ~TempTree() { fs::remove_all(root); }
    void write(const std::string& rel, const std::string& text) const {
        fs::create_directories((root / rel).parent_path());
        std::ofstream(root / rel, std::ios::binary) << text;
    }
};

} // namespace layering
