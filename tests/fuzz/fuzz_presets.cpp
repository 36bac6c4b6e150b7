// Fuzzes the material presets file (material::loadPresets, presets.json) and applying each
// preset read to the default material.
#include "fuzz_common.h"

#include "material/material.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "presets.json");
    fuzz::expectCleanError([&] {
        for (const material::Preset& p : material::loadPresets(path))
            material::validate(material::applyPreset(p, material::MaterialParams{}), p.name);
    });
    return 0;
}
