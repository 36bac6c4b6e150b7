#!/usr/bin/env bash
# Everything the GPU test bundle can say about the machine it runs on, in one call with one time
# budget: the card and driver, every gl test (the ones that stall the GPU on purpose one at a time
# after the others) and every capture's replay, the benchmarks whose figures README records
# (reload, hierarchy, path tracer, point cloud), and the driver's reset messages (Xid) if the
# kernel log can be read. Each part gets what is left of the budget, so the results are written
# whatever part runs long; a part that does not fit is listed as skipped.
#   ./card-checks.sh [--budget S] [--jobs N] [--timeout S] [--filter REGEX] [--benches LIST]
#                    [--out DIR]
# --budget: seconds for all of it (default 540); --jobs: tests at a time (default: cores / 2, at
# most 8); --timeout: seconds per test (default 90); --filter: only the tests whose names match;
# --benches: which, of "reload hierarchy pathtrace" (the default; "" for none); --out: where the
# results go (default ./card-results): info.txt, summary.txt, tests_gl.txt, tests_replay.txt,
# benches.txt and results.tgz (each test's log and the benchmarks' whole output).
# Exit status: 0 when every part ran and passed, 1 otherwise.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
budget=540
jobs=$(($(nproc 2>/dev/null || echo 2) / 2))
((jobs < 1)) && jobs=1
((jobs > 8)) && jobs=8
limit=90
filter=""
benches="reload hierarchy pathtrace"
out=$PWD/card-results
while [[ $# -gt 0 ]]; do
  case $1 in
    --budget) budget=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --filter) filter=$2; shift 2 ;;
    --benches) benches=$2; shift 2 ;;
    -h|--help) sed -n 2,15p "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "card-checks.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
for n in "$budget" "$jobs" "$limit"; do
  [[ $n =~ ^[1-9][0-9]*$ ]] || { echo "card-checks.sh: expected a positive count, got '$n'" >&2; exit 2; }
done
for b in $benches; do
  [[ $b =~ ^(reload|hierarchy|pathtrace)$ ]] ||
    { echo "card-checks.sh: --benches: unknown benchmark '$b' (reload hierarchy pathtrace)" >&2; exit 2; }
done

start=$(date +%s)
left() { echo $((budget - ($(date +%s) - start))); }
rm -rf "$out"
mkdir -p "$out/work"
summary=$out/summary.txt
: >"$summary"
failed=0
note() { echo "$*" | tee -a "$summary"; }

export LD_LIBRARY_PATH=$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
nvidiaEgl=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
if [[ -z ${__EGL_VENDOR_LIBRARY_FILENAMES:-} && -f $nvidiaEgl ]] &&
   ! ls /usr/share/glvnd/egl_vendor.d/*.json /etc/glvnd/egl_vendor.d/*.json >/dev/null 2>&1; then
  export __EGL_VENDOR_LIBRARY_FILENAMES=$nvidiaEgl
fi
workbench=("$here/bin/bssrdf-workbench" --root "$here/src")

{
  echo "date: $(date -u +%FT%TZ)"
  echo "bundle: $(sed -n 2p "$here/BUNDLE.txt" 2>/dev/null)"
  echo "machine: $(uname -srm), $(nproc) cores"
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1
  fi
  # the renderer the workbench gets: the GL slab tracer names it in its table's header
  if timeout 60 "${workbench[@]}" slab --gpu --paths 10000 --out "$out/work/slab.csv" \
       >"$out/work/slab.txt" 2>&1; then
    echo "GL: $(sed -n 's/^# GPU (\(.*\)) path-traced.*/\1/p' "$out/work/slab.csv" | head -n 1)"
  else
    echo "GL: none: $(tail -n 1 "$out/work/slab.txt")"
  fi
} >"$out/info.txt" 2>&1
cat "$out/info.txt"

# part NAME RESERVE CMD...: runs CMD with what is left of the budget but RESERVE seconds (kept for
# the parts after it), output to NAME.txt; one summary line.
part() {
  local name=$1 reserve=$2 t0 rc s
  shift 2
  s=$(($(left) - reserve))
  if ((s < 20)); then
    note "skipped $name: the budget was spent"
    failed=1
    return
  fi
  t0=$(date +%s)
  timeout "$s" "$@" >"$out/work/$name.txt" 2>&1
  rc=$?
  # a stopped run of tests leaves the tests it had started (each under its own timeout, in a
  # process group of its own): they go too, so that nothing else runs on the card after it
  ((rc == 124)) && pkill -f "$here/bin/" && sleep 1
  ((rc == 0)) || failed=1
  note "$( ((rc == 124)) && echo "stopped" || { ((rc == 0)) && echo passed || echo "failed (rc $rc)"; }) $name in $(($(date +%s) - t0)) s"
}

# The tests that keep the GPU busy for seconds on purpose, or kill a child in a dispatch.
stalling='ProbeFixture|LoopBudget|RunsAway|DoesNotFinish|GlReset'
part tests_replay $((budget / 2)) "$here/run-tests.sh" --jobs "$jobs" --timeout "$limit" \
  --label replay --filter "$filter" --out "$out/work/replay"
part tests_gl $((budget / 6)) "$here/run-tests.sh" --jobs "$jobs" --timeout "$limit" --label gl \
  --filter "$filter" --serial "$stalling" --out "$out/work/gl"
for t in replay gl; do
  cp "$out/work/tests_$t.txt" "$out/tests_$t.txt" 2>/dev/null
done
# The benchmarks README records, one at a time, nothing else on the card.
[[ " $benches " == *" reload "* ]] &&
  part bench_reload $((budget / 8)) "${workbench[@]}" bench reload --runs 5
[[ " $benches " == *" hierarchy "* ]] &&
  part bench_hierarchy $((budget / 16)) "${workbench[@]}" bench hierarchy
[[ " $benches " == *" pathtrace "* ]] &&
  part bench_pathtrace 10 "${workbench[@]}" bench pathtrace --seconds 1
for b in $benches; do
  [[ -f $out/work/bench_$b.txt ]] && { echo "== bench $b"; cat "$out/work/bench_$b.txt"; }
done >"$out/benches.txt"
if dmesg >/dev/null 2>&1; then
  dmesg | grep -i 'xid' >"$out/work/xid.txt"
  note "kernel log: $(wc -l <"$out/work/xid.txt") Xid lines (work/xid.txt)"
else
  note "kernel log: not readable here"
fi
tar -czf "$out/results.tgz" -C "$out" work 2>/dev/null && rm -rf "$out/work"
note "card checks: $( ((failed == 0)) && echo "all passed" || echo "not all passed") in $(($(date +%s) - start)) s"
exit $failed
