// The preset chooser of the Parameters and Scoreboard panels: the measured media of
// materials/presets.json grouped by the publication they come from, each entry's source and notes
// (disputed values) in its tooltip, presets the models cannot use shown but disabled with the
// reason.
#pragma once

#include <string>

namespace app {

class Workbench;
struct MaterialSettings;

// Draws the combo labelled `label`; choosing a preset applies it to `s`. Returns true when it did.
bool presetCombo(const char* label, Workbench& wb, MaterialSettings& s);

} // namespace app
