// Shared by the tests that render the scene: settings small enough for a test.
#pragma once

#include "pipeline/scene_stage.h"

namespace testsupport {

// A scene small enough for tests: 3000 points, no disk cache (never the user's point-cloud
// cache), a 96 × 54 frame, a 256² shadow map.
inline void useSmallScene(app::SceneSettings& s) {
    s.points.points = 3000;
    s.useCache = false;
    s.render.width = 96;
    s.render.height = 54;
    s.light.shadowMapSize = 256;
}

} // namespace testsupport
