#!/usr/bin/env bash
# The GPU test bundle runs from an empty folder, and from its own files only (ctest:
# gpu_bundle_runs_from_an_empty_folder):
# packs the build (fast compression), unpacks it into a new folder, checks that no test command
# names the build or source folder, and runs there a few tests of every kind: gl and unit tests,
# ones that run the executable (BW_EXE) or read the source tree (BW_SOURCE_ROOT), and a replay.
#   tests/bundle/check.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
BW_BUNDLE_FAST=1 "$here/pack.sh" "$build" "$tmp/bundle.tar.xz"
mkdir "$tmp/empty"
tar -C "$tmp/empty" -xJf "$tmp/bundle.tar.xz"
b=$tmp/empty/bssrdf-workbench-tests
src=$(cd "$here/../.." && pwd)
if grep -q -e "$build" -e "$src/" "$b/tests.tsv"; then
  echo "check: tests.tsv names the build or source folder" >&2
  exit 1
fi
filter='^(replay_dipole_marble|Suite[.]SpecsAreCanonical|GeometryCli[.]BadInputsNameTheirArgument'
filter+='|McoCli[.]BadMcmlInputsNameTheFile|PencilProfileGpu[.]MultiplierParameterScalesTheProfile'
filter+='|AppLayering[.]NoFolderUsesAFolderAboveItAndNoFilesIncludeEachOther)$'
(cd "$tmp/empty" && "$b/run-tests.sh" --jobs 2 --filter "$filter" --serial '^(Suite|McoCli)[.]' \
   --out "$tmp/results") | tee "$tmp/summary.txt"
grep -q "^summary: 6 passed, 0 failed, 0 timed out, 0 skipped, of 6" "$tmp/summary.txt"
# --serial: the two it names ran after the other four, one at a time
sed -n '/^one at a time/,$p' "$tmp/summary.txt" | grep -c '^passed' | grep -qx 2
# card-checks.sh, the one call for a GPU machine: the card's name, the tests of both labels, the
# summary and the logs, here with one test of each label and no benchmark; a bad argument refused
(cd "$tmp/empty" && "$b/card-checks.sh" --budget 300 --jobs 2 --benches "" \
   --filter '^(replay_dipole_marble|PencilProfileGpu[.]MultiplierParameterScalesTheProfile)$' \
   --out "$tmp/card") | tee "$tmp/card.txt"
grep -q '^GL: .' "$tmp/card/info.txt"
if grep -q '^GL: none' "$tmp/card/info.txt"; then
  echo "check: card-checks.sh found no GL context" >&2
  exit 1
fi
grep -q '^passed tests_replay in' "$tmp/card/summary.txt"
grep -q '^passed tests_gl in' "$tmp/card/summary.txt"
grep -q '^card checks: all passed' "$tmp/card/summary.txt"
grep -q '^summary: 1 passed, 0 failed' "$tmp/card/tests_gl.txt"
tar -tzf "$tmp/card/results.tgz" >"$tmp/card-files.txt"
grep -q 'work/replay/results.tsv' "$tmp/card-files.txt"
if "$b/card-checks.sh" --benches "reload speed" --out "$tmp/card2" 2>"$tmp/card2.txt"; then
  echo "check: card-checks.sh took an unknown benchmark" >&2
  exit 1
fi
grep -q "unknown benchmark 'speed'" "$tmp/card2.txt"
# ...and from there only: without the bundle's copy of the test data and of the executable, the
# tests that read them through BW_SOURCE_ROOT and BW_EXE fail (had they fallen back on the
# build's paths, they would pass)
rm -r "$b/src/tests/data/mcml"
mv "$b/bin/bssrdf-workbench" "$b/bin/moved-away"
(cd "$tmp/empty" && "$b/run-tests.sh" --jobs 2 --out "$tmp/results2" \
   --filter '^(McoCli[.]BadMcmlInputsNameTheFile|GeometryCli[.]BadInputsNameTheirArgument)$' ||
   true) | tee "$tmp/summary2.txt"
grep -q "^summary: 0 passed, 2 failed" "$tmp/summary2.txt"
