// material: small helpers for error messages (channel names; numbers via core/text.h).
#pragma once

#include "core/text.h"

namespace material::detail {

inline const char* channelName(int c) {
    static const char* kChannel[3] = {"R", "G", "B"};
    return kChannel[c];
}

} // namespace material::detail
