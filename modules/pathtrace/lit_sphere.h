// pathtrace lit sphere: the lit-sphere setup and image (litsphere/litsphere.h) under the names
// the path tracers use.
#pragma once

#include "litsphere/litsphere.h"

namespace pathtrace {

using LitSphereSetup = litsphere::Setup;
using Image = litsphere::Image;

} // namespace pathtrace
