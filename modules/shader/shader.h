// shader: the project's one shader builder, below every module that builds GL programs
// (bssrdf, render, irradiance, pathtrace). It assembles GLSL from files with #include
// resolution and `#line` directives whose line numbers also encode the file (assembly.h:
// Mesa reports every error against source string 0), maps a driver's info log back to
// path:line (diagnostics.h), and records the files each program was built from, so that hot
// reload rebuilds exactly the programs that read a changed file (program.h).
#pragma once

#include "shader/assembly.h"
#include "shader/diagnostics.h"
#include "shader/program.h"
