#!/bin/sh
# Regenerates docs/geometry/: every shipped model on the whole geometry suite (mesh/suite.h) for
# Marble and Skin1 at the default sizes (48 px, 64 reference paths per covered pixel in each of
# 3 estimates, 32 BSSRDF samples per pixel), with the pictures of the green channel. Measured:
# 712 s on 2 CPU cores with llvmpipe (150 references traced). Run from the repository root after
# building:
#   sh docs/geometry/regenerate.sh [path/to/bssrdf-workbench]
set -e
exe=${1:-build/app/bssrdf-workbench}
rm -rf docs/geometry/images
"$exe" compare --geometry --pictures G --out docs/geometry
