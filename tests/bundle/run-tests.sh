#!/usr/bin/env bash
# Runs the bundle's tests (tests.tsv: name, labels, command) from wherever the bundle lies, each
# in a folder of its own with a time limit, N at a time, and prints a summary: passed, failed and
# timed out, with each test's seconds (results.tsv) and the output of the ones that did not pass
# (logs/). Needs bash, coreutils and a GL driver with EGL; nothing of the build machine.
#   ./run-tests.sh [--jobs N] [--timeout S] [--label gl|unit|replay|slow] [--filter REGEX]
#                  [--serial REGEX] [--out DIR]
# --serial: the selected tests whose names match run one at a time after the others (tests
# that keep the GPU busy for seconds on purpose, e.g. 'ProbeFixture|LoopBudget|RunsAway'), so
# their stalls and the driver's recovery from a killed dispatch do not reach the other tests.
# Exit status: 0 when every selected test passed, 1 otherwise.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
jobs=$(nproc 2>/dev/null || echo 2)
limit=300
label=""
filter=""
serial=""
out=$PWD/bundle-results
while [[ $# -gt 0 ]]; do
  case $1 in
    --jobs) jobs=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --label) label=$2; shift 2 ;;
    --filter) filter=$2; shift 2 ;;
    --serial) serial=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n 2,11p "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "run-tests.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[[ $jobs =~ ^[1-9][0-9]*$ ]] || { echo "run-tests.sh: --jobs: expected a count, got '$jobs'" >&2; exit 2; }
[[ $limit =~ ^[1-9][0-9]*$ ]] || { echo "run-tests.sh: --timeout: expected seconds, got '$limit'" >&2; exit 2; }

export LD_LIBRARY_PATH=$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export PATH=$here/bin:$PATH # GNU parallel, packed beside the executables
export BW_TEST_SOURCE_ROOT=$here/src BW_TEST_EXE=$here/bin/bssrdf-workbench
# glvnd finds the vendor's EGL library through its JSON; NVIDIA containers keep it here
nvidiaEgl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [[ -z ${__EGL_VENDOR_LIBRARY_FILENAMES:-} && -f $nvidiaEgl ]] &&
   ! ls /usr/share/glvnd/egl_vendor.d/*.json /etc/glvnd/egl_vendor.d/*.json >/dev/null 2>&1; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=$nvidiaEgl
fi

rm -rf "$out"
mkdir -p "$out/logs" "$out/work"
selected=$out/selected.tsv
awk -F'\t' -v label="$label" -v re="$filter" \
  '(label == "" || index("," $2 ",", "," label ",")) && (re == "" || $1 ~ re)' \
  "$here/tests.tsv" >"$selected"
total=$(wc -l <"$selected")
[[ $total -gt 0 ]] || { echo "run-tests.sh: no test matches" >&2; exit 2; }
echo "bundle: $(sed -n 2p "$here/BUNDLE.txt")"
echo "running $total tests, $jobs at a time, $limit s each (results in $out)"

one() { # index: runs line `index` of the selection, appends its result line
  local i=$1 line name cmd start rc status secs
  line=$(sed -n "${i}p" "$selected")
  name=${line%%$'\t'*}
  IFS=$'\t' read -r -a cmd <<<"$(cut -f3- <<<"$line")"
  for k in "${!cmd[@]}"; do
    cmd[$k]=${cmd[$k]//@BIN@/$here/bin}
    cmd[$k]=${cmd[$k]//@SRC@/$here/src}
  done
  mkdir -p "$out/work/$i"
  start=$(date +%s.%N)
  (cd "$out/work/$i" && BSSRDF_WORKBENCH_CACHE=$out/work/$i/cache BSSRDF_WORKBENCH_GL_BARRIERS=1 \
     timeout -k 5 "$limit" "${cmd[@]}") >"$out/logs/$i.log" 2>&1
  rc=$?
  secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}')
  if [[ $rc -eq 0 ]] && ! grep -q '\[  SKIPPED \]' "$out/logs/$i.log"; then status=passed
  elif [[ $rc -eq 0 ]]; then status=skipped
  elif [[ $rc -eq 124 || $rc -eq 137 ]]; then status=timeout
  else status=failed; fi
  [[ $status == passed ]] && rm -rf "$out/work/$i" "$out/logs/$i.log"
  printf '%s\t%s\t%s\t%s\n' "$status" "$secs" "$name" "$i" >>"$out/results.tsv"
  printf '%-8s %7ss  %s\n' "$status" "$secs" "$name"
}
export -f one
export here out selected limit
begin=$(date +%s)
if [[ -z $serial ]]; then
  seq 1 "$total" | xargs -P "$jobs" -I{} bash -c 'one {}'
else
  awk -F'\t' -v re="$serial" '$1 !~ re {print NR}' "$selected" | xargs -r -P "$jobs" -I{} bash -c 'one {}'
  echo "one at a time: the tests matching '$serial'"
  awk -F'\t' -v re="$serial" '$1 ~ re {print NR}' "$selected" | xargs -r -P 1 -I{} bash -c 'one {}'
fi
wall=$(( $(date +%s) - begin ))

passed=$(grep -c '^passed' "$out/results.tsv" || true)
failed=$(grep -c '^failed' "$out/results.tsv" || true)
timedout=$(grep -c '^timeout' "$out/results.tsv" || true)
skipped=$(grep -c '^skipped' "$out/results.tsv" || true)
echo
echo "summary: $passed passed, $failed failed, $timedout timed out, $skipped skipped, of $total, in ${wall} s"
echo "slowest:"
sort -t$'\t' -k2,2 -g -r "$out/results.tsv" | awk -F'\t' 'NR <= 10 {printf "  %7ss  %s  %s\n", $2, $1, $3}'
if [[ $((failed + timedout)) -gt 0 ]]; then
  echo "not passed (log: $out/logs/<n>.log):"
  grep -E '^(failed|timeout)' "$out/results.tsv" | awk -F'\t' '{printf "  %s  %s  (logs/%s.log)\n", $1, $3, $4}'
  exit 1
fi
exit 0
