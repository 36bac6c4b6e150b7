#!/usr/bin/env bash
# Packs the GPU test bundle (README, "On a GPU machine"): the Release build's executable and test
# executables, the shared libraries they load except the C library's (glibc stays the target's;
# the GL loaders libEGL/libGL/libOpenGL/libGLdispatch are glvnd's, so the target's driver
# provides the vendor library), the tracked source tree (materials, shaders, captures, test data
# and the sources the layering tests read), the test list ctest knows with its labels, and
# run-tests.sh, into one .tar.xz that runs from any folder.
#   tests/bundle/pack.sh BUILD_DIR OUT.tar.xz
set -euo pipefail
build=$(cd "$1" && pwd)
out=$2
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
name=bssrdf-workbench-tests
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
root=$stage/$name
mkdir -p "$root/bin" "$root/lib" "$root/src"

# the source tree as committed (and any untracked file git does not ignore)
(cd "$src" && git ls-files -z --cached --others --exclude-standard |
   xargs -0 cp --parents -t "$root/src" 2>/dev/null || true)

# the test list: name, labels, command with the build and source paths made relative (the tests
# that run the build's executables: not the bundle's own check, which runs this script)
ctest --test-dir "$build" --show-only=json-v1 >"$stage/tests.json"
python3 - "$stage/tests.json" "$build" "$src" >"$root/tests.tsv" <<'PY'
import json, os, sys
tests, build, src = json.load(open(sys.argv[1]))["tests"], sys.argv[2], sys.argv[3]
def rel(a):
    a = a.replace(build + "/app/bssrdf-workbench", "@BIN@/bssrdf-workbench")
    if a.startswith(build + "/tests/"):
        a = "@BIN@/" + a.rsplit("/", 1)[1]
    return a.replace(src, "@SRC@")
unbuilt = [t["name"][:-len("_NOT_BUILT")] for t in tests if t["name"].endswith("_NOT_BUILT")]
if unbuilt:  # (the Release tree of CI's `./run test` builds only the executables it runs)
    print(f"pack: {len(unbuilt)} test executables are not built ({', '.join(unbuilt[:4])}…)",
          file=sys.stderr)
    if os.environ.get("BW_BUNDLE_FAST") != "1":
        sys.exit("pack: build the whole tree first (cmake --build BUILD_DIR)")
for t in tests:
    if not t.get("command", [""])[0].startswith(build + "/"):
        continue  # not a test executable of the build (this bundle's own check), or not built
    labels = next((p["value"] for p in t.get("properties", []) if p["name"] == "LABELS"), [])
    if "window" in labels:
        continue  # the window tests start an X server (Xvfb), which a GPU machine lacks
    print("\t".join([t["name"], ",".join(labels)] + [rel(a) for a in t["command"]]))
PY

# executables: the workbench and every test executable the list runs
cp "$build/app/bssrdf-workbench" "$root/bin/"
cut -f3 "$root/tests.tsv" | sort -u | while read -r exe; do
  f=${exe#@BIN@/}
  [[ $f == bssrdf-workbench ]] && continue
  p=$(find "$build/tests" -type f -name "$f" -perm -u+x -print -quit)
  [[ -n $p ]] || { echo "pack: test executable $f not found" >&2; exit 1; }
  cp "$p" "$root/bin/"
done
if grep -q "$src\|$build" "$root/tests.tsv"; then
  echo "pack: a test command still names $src or $build" >&2
  exit 1
fi

# shared libraries, without the C library's own (the target's glibc must be this one's or newer)
glibc='/(libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|ld-linux[^/]*)\.so[^/]*$'
for exe in "$root"/bin/*; do ldd "$exe"; done | awk '/=> \// {print $3}' | sort -u |
  grep -Ev "$glibc" | while read -r lib; do cp -L "$lib" "$root/lib/"; done
# what libepoxy opens by name at run time: glvnd's loaders
for lib in libEGL.so.1 libGL.so.1 libOpenGL.so.0 libGLdispatch.so.0 libGLX.so.0; do
  # (awk reads to the end: an early exit leaves ldconfig writing into a closed pipe, SIGPIPE, and
  # under pipefail the pack stopped without a word, now and then)
  p=$(ldconfig -p | awk -v l="$lib" '$1 == l && /x86-64/ && !f {f = $NF} END {if (f) print f}')
  [[ -n $p ]] && cp -L "$p" "$root/lib/"
done

strip --strip-unneeded "$root"/bin/* "$root"/lib/* 2>/dev/null || true
# GNU parallel (a Perl script; the target needs perl), after ldd and strip, which take ELF files
# only: the sharding tests run the README's `parallel` command lines
if p=$(command -v parallel); then cp -L "$p" "$root/bin/"; fi
cp "$src/tests/bundle/run-tests.sh" "$src/tests/bundle/card-checks.sh" "$root/"
chmod +x "$root/run-tests.sh" "$root/card-checks.sh"
# (awk reads to the end: `head` would leave ldd writing into a closed pipe, SIGPIPE, exit 141)
glibcVersion=$(ldd --version | awk 'NR == 1 {print $NF}')
cat >"$root/BUNDLE.txt" <<TXT
bssrdf-workbench test bundle
commit $(cd "$src" && git rev-parse --short HEAD) $(cd "$src" && git status --porcelain | grep -q . && echo "(with local changes)")
built on $(. /etc/os-release && echo "$PRETTY_NAME"), glibc $glibcVersion (the target needs this or newer)
tests $(wc -l <"$root/tests.tsv")
TXT
mkdir -p "$(dirname "$out")"
# xz with a large window: the test executables share most of their code (the app's libraries).
# BW_BUNDLE_FAST=1 (the bundle's own test) compresses little, skips the size check and packs the
# test executables that are built, where some are not.
level=-9
[[ ${BW_BUNDLE_FAST:-} == 1 ]] && level=-0
XZ_OPT="$level -T0" tar -C "$stage" -cJf "$out" "$name"
size=$(stat -c %s "$out")
if [[ ${BW_BUNDLE_FAST:-} != 1 && $size -gt $((64 << 20)) ]]; then
  echo "pack: $out is $((size >> 20)) MiB, over the 64 MiB a GPU machine's working tree carries" >&2
  exit 1
fi
echo "wrote $out ($(du -h "$out" | cut -f1), $(wc -l <"$root/tests.tsv") tests)"
