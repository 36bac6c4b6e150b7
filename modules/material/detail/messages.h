// material: small helpers for error messages (channel names, compact numbers).
#pragma once

#include <cstdio>
#include <string>

namespace material::detail {

inline const char* channelName(int c) {
    static const char* kChannel[3] = {"R", "G", "B"};
    return kChannel[c];
}

inline std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

} // namespace material::detail
